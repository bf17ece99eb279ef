/*
 * Crack-free tessellation of sets of NURBS surfaces (see surface.h).
 *
 * Structure: every surface is cut into cells (non-empty knot spans); the
 * grid nodes and cell edges of a surface are shared by its cells. Boundary
 * nodes of all surfaces are welded by exact position, boundary edges with
 * the same welded end nodes whose curves coincide become partners, and
 * edges whose points all coincide are collapsed (poles). Each edge is
 * sampled once (by its owner: the lower id of a pair), with the count the
 * finer of the cells around it wants, so neighbouring cells use the very
 * same vertices. Cells are triangulated in parameter space: as a grid when
 * their edges carry exactly the cell's grid, otherwise an interior grid
 * joined to the edge samples by strips.
 *
 * Adaptive sizing: Filip, Magedson and Markot's bound
 * (du^2 Muu + 2 du dv Muv + dv^2 Mvv) / 8 with sampled second derivatives,
 * then every triangle is checked against the surface (dense barycentric
 * sampling at its parameter-space position) and the cells over the
 * tolerance are refined until all pass. Then each cell takes the M x N
 * grid with the fewest quads that passes the same check (a search over M,
 * see optimise_cell), so no uniform u x v grid per span that passes needs
 * fewer triangles; the cells it changed are checked again as stitched.
 */
#include "surface/surface_internal.h"
#include "spatial/spatial_internal.h"

#include <float.h>
#include <string.h>

#define NONE32 UINT32_MAX
#define LOCATE SIZE_MAX
#define MAX_GRID 65536u
#define GRID_MEMO 16 /* grid search answers remembered */
#define MAX_PASSES 40
/* adaptive: a cell far under the tolerance is coarsened toward this fraction
 * of it (then checked again) */
#define COARSEN_TARGET 0.95
/* grid-line warps: intervals of the density samples; the smallest ratio of
 * the largest to the smallest density that warps the lines; the density
 * floor, a fraction of the mean (no line spacing above about 1/0.3 times
 * the mean: the density sees one direction's chords, while a quad's error
 * also has the other direction's and the twist's terms). Measured on the
 * teapot at 1e-3: ratio 1.5 and floor 0.05 gave 60,690 triangles, 1.8 and
 * 0.3 give 52,236 (uniform lines 65,270); the sphere octant with weights
 * 0.1..10 makes 1,269 either way. */
#define WARP_N 32
#define WARP_RATIO 1.8
#define WARP_FLOOR 0.3

/* ------------------------------------------------------------ structures */

typedef struct ts_surf {
    const geom_nurbs_surface *s;
    uint32_t orig; /* index of the input surface (a surface is cut into
                      pieces at its discontinuities) */
    size_t nbu, nbv;
    double *ub, *vb;    /* nbu+1, nbv+1 break values */
    size_t *ku, *kv;    /* span per cell column / row, or LOCATE */
    size_t cell0, node0, uedge0, vedge0;
    double dom[4];
    int flip;
    /* grid-line warps (tess_warp.c) per cell column (dir 0, along u) and
     * row (dir 1): WARP_N + 1 values of F each, used where won[dir][a] */
    double *wF[2];
    uint8_t *won[2];
} ts_surf;

typedef struct ts_cell {
    uint32_t surf, a, b;
    double u0, u1, v0, v1;
    size_t ku, kv;
    uint32_t M, N;
    uint32_t eb, et, el, er; /* bottom, top, left, right edges */
    uint32_t vbase;          /* first interior vertex */
    double err, ang;   /* largest chordal error and normal angle of its triangles */
    double esum;       /* mean of the per-triangle maximum errors (a mean: no overflow) */
    double wu, wv;     /* parameters of its worst sample (where a grid search looks first) */
    size_t ecnt;       /* triangles checked */
    uint32_t sig[6];
    int checked;
} ts_cell;

typedef struct ts_node {
    double p[3];
    uint32_t vert;
    uint8_t boundary;
} ts_node;

typedef struct ts_edge {
    uint32_t surf;
    uint32_t cellA, cellB; /* below/left and above/right cells (NONE32 if absent) */
    uint32_t n0, n1;
    uint8_t dir;      /* 0: u varies (constant v), 1: v varies */
    uint8_t boundary; /* on the surface's domain boundary */
    uint8_t collapsed;
    uint8_t reversed; /* parameter direction opposite to the owner's */
    int8_t tau;       /* CCW traversal sign as a boundary edge */
    uint32_t partner;
    uint32_t owner;
    double c, t0, t1; /* constant parameter, varying range */
    uint32_t nseg;
    uint32_t vbase; /* owner: first of its nseg-1 interior vertices */
} ts_edge;

/* exact-value pool with deduplication */
typedef struct ts_pool {
    size_t ncomp;
    double *vals;
    size_t n, cap;
    geom__hindex hash; /* core's hash index over the values */
} ts_pool;

typedef struct ts {
    const geom_allocator *alloc;
    const geom_surface_tess_options *opt;
    geom_diag *diag;
    ts_surf *surf;
    size_t nsurf;
    ts_cell *cells;
    size_t ncells;
    ts_node *nodes;
    uint32_t *parent; /* union-find over the nodes (welded seams) */
    size_t nnodes;
    ts_edge *edges;
    size_t nedges;
    double tol, weld_tol, ang_tol;
    int adaptive;
    int ksub;
    size_t max_tri;
    /* vertices of the current pass */
    double *pos;
    size_t nverts, cap_verts;
    /* per-cell local samples */
    double *lu, *lv;
    uint32_t *lvert;
    double *lnorm;
    size_t nloc, cap_lu, cap_lv, cap_lvert, cap_lnorm;
    /* triangles of the current cell (local sample indices) */
    uint32_t *ltri;
    uint32_t *lmate; /* 2 per local triangle: the triangles across its inner
                        sides (a quad's other half; a strip's neighbours), or NONE32 */
    uint8_t *ldiag;  /* per local triangle: bit s set for each inner side s
                        (0 X1X2, 1 X0X2, 2 X0X1; see tri_error) */
    size_t nltri, cap_ltri, cap_lmate, cap_ldiag;
    /* output */
    uint32_t *tri;    /* 3 per triangle: global vertex ids */
    uint32_t *tcorn;  /* 9 per triangle: normal, uv, tangent pool indices */
    uint32_t *tsurf;  /* surface per triangle */
    size_t cap_tsurf;
    size_t ntri, cap_tri, cap_tcorn;
    ts_pool pn, puv, pt;
    /* scratch for evaluation */
    geom__scratch sc;
    double *lat; /* the error check's lattice samples: 3 (K+1)(K+2)/2 */
    size_t evals;
    size_t limit_normals;
    double normal_weld;    /* radians; 0: corner normals not welded */
    size_t welded_normals; /* corners whose normal was welded */
    int counting; /* count limit normals (the output pass) */
    double prune; /* > 0 while pruning uniform grids: the margin their
                     positions may differ by (see uniform_search) */
    int warp_on;  /* the cells' grid lines follow their warps (adaptive
                     mode, not while running uniform grids) */
    /* the error check's samples of the cell being checked, by their exact
     * (u, v) (direct-mapped; neighbouring triangles compute the samples of
     * their shared sides with the very same parameters) */
    struct ts_memo *memo; /* MEMO_SIZE entries, or NULL */
    uint32_t memo_gen;    /* entries of other checks are stale */
    int memo_on;          /* in check_cell */
    /* the grid searches' recent answers, by the walk's start (see
     * grid_search): congruent cells (the sphere's spans, the teapot's
     * mirrored patches) start from the answer the last one found */
    struct ts_grid_memo {
        double tol;
        uint32_t mfirst, mlb, nlb, m, n;
    } grid_memo[GRID_MEMO];
    unsigned grid_memo_next;
} ts;

#define MEMO_BITS 15
#define MEMO_SIZE ((size_t)1 << MEMO_BITS)
typedef struct ts_memo {
    double u, v, p[3];
    uint32_t gen;
} ts_memo;

/* --------------------------------------------------------------- memory */

static void *ts_alloc(ts *T, size_t n, size_t size)
{
    size_t bytes;
    if (geom__size_mul(n ? n : 1, size, &bytes) != GEOM_OK)
        return NULL;
    return geom__alloc(T->alloc, bytes);
}

static void ts_free(ts *T, void *p, size_t n, size_t size)
{
    geom__free(T->alloc, p, (n ? n : 1) * size);
}

/* ----------------------------------------------------------------- pools */

static geom_status pool_add(ts *T, ts_pool *P, const double *v, uint32_t *idx)
{
    size_t nc = P->ncomp;
    double key[4];
    for (size_t c = 0; c < nc; ++c)
        key[c] = v[c] == 0.0 ? 0.0 : v[c];
    uint64_t h = geom__hash_doubles(key, nc);
    size_t it = 0;
    uint32_t cand;
    while ((cand = geom__hindex_next(&P->hash, h, &it)) != UINT32_MAX)
        if (memcmp(P->vals + (size_t)cand * nc, key, nc * sizeof(double)) == 0) {
            *idx = cand;
            return GEOM_OK;
        }
    if (P->n >= NONE32 - 1)
        return GEOM_ERR_LIMIT;
    size_t cap = P->cap;
    geom_status st = geom__grow(T->alloc, (void **)&P->vals, &cap, (P->n + 1) * nc, sizeof(double));
    if (st != GEOM_OK)
        return st;
    P->cap = cap;
    if (P->n + 1 > P->hash.cap / 2) {
        st = geom__hindex_reserve(&P->hash, T->alloc, P->n + 1);
        if (st != GEOM_OK)
            return st;
        it = 0; /* the index moved: find the free slot again */
        while (geom__hindex_next(&P->hash, h, &it) != UINT32_MAX)
            ;
    }
    memcpy(P->vals + P->n * nc, key, nc * sizeof(double));
    geom__hindex_insert_at(&P->hash, h, it, (uint32_t)P->n);
    *idx = (uint32_t)P->n++;
    return GEOM_OK;
}

static void pool_free(ts *T, ts_pool *P)
{
    if (P->vals)
        ts_free(T, P->vals, P->cap, sizeof(double));
    geom__hindex_free(&P->hash, T->alloc);
    memset(P, 0, sizeof *P);
}

/* ------------------------------------------------------------ evaluation */

static void cell_spans(const ts *T, const ts_cell *c, double u, double v, size_t *ku, size_t *kv)
{
    if (c->ku != LOCATE) {
        *ku = c->ku;
        *kv = c->kv;
        return;
    }
    /* right limits, except at the cell's upper ends (a piece ends at a
     * discontinuity or at the end of the domain) */
    const geom_nurbs_surface *s = T->surf[c->surf].s;
    *ku = geom__bs_span(s->degree_u, s->nu, s->knots_u, u, u >= c->u1);
    *kv = geom__bs_span(s->degree_v, s->nv, s->knots_v, v, v >= c->v1);
}

static void cell_point(ts *T, const ts_cell *c, double u, double v, double *out)
{
    size_t ku, kv;
    cell_spans(T, c, u, v, &ku, &kv);
    geom__surface_span_point(T->surf[c->surf].s, ku, kv, u, v, out, T->sc.mem);
    T->evals++;
}

static void cell_derivs(ts *T, const ts_cell *c, double u, double v, int d, double *out)
{
    size_t ku, kv;
    cell_spans(T, c, u, v, &ku, &kv);
    geom__surface_span_derivs(T->surf[c->surf].s, ku, kv, u, v, d, out, T->sc.mem);
    T->evals++;
}

/* Normal (and unit dP/du) at (u, v) of cell c, the limit entering the cell
 * at degenerate points; falls back to the cell centre's normal. */
static void cell_normal(ts *T, const ts_cell *c, double u, double v, double *n, double *t)
{
    size_t ku, kv;
    cell_spans(T, c, u, v, &ku, &kv);
    double mu = 0.5 * (c->u0 + c->u1), mv = 0.5 * (c->v0 + c->v1);
    int su = u < mu ? 1 : -1, sv = v < mv ? 1 : -1;
    const geom_nurbs_surface *s = T->surf[c->surf].s;
    int how = geom__surface_span_normal(s, ku, kv, u, v, su, sv, n, t, T->sc.mem);
    T->evals++;
    if (how == GEOM_SURFACE_NORMAL_LIMIT && T->counting)
        T->limit_normals++;
    if (how == GEOM_SURFACE_NORMAL_NONE) {
        cell_spans(T, c, mu, mv, &ku, &kv);
        how = geom__surface_span_normal(s, ku, kv, mu, mv, 1, 1, n, t, T->sc.mem);
        if (how == GEOM_SURFACE_NORMAL_NONE) {
            n[0] = n[1] = 0.0, n[2] = 1.0;
            t[0] = 1.0, t[1] = t[2] = 0.0;
        }
    }
}

/* |a - b| for coordinates anywhere in the range of double: halved
 * differences (no overflow), scaled before squaring. NaN stays NaN (a NaN
 * distance must never read as 0, which would collapse edges). */
static double dist3(const double *a, const double *b)
{
    double d[3] = {0.5 * a[0] - 0.5 * b[0], 0.5 * a[1] - 0.5 * b[1], 0.5 * a[2] - 0.5 * b[2]};
    if (isnan(d[0]) || isnan(d[1]) || isnan(d[2]))
        return NAN;
    double m = fmax(fabs(d[0]), fmax(fabs(d[1]), fabs(d[2])));
    if (m == 0.0)
        return 0.0;
    if (!isfinite(m))
        return INFINITY;
    d[0] /= m, d[1] /= m, d[2] /= m;
    return 2.0 * m * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* The cell an edge is evaluated through. */
static const ts_cell *edge_cell(const ts *T, const ts_edge *e)
{
    return &T->cells[e->cellB != NONE32 ? e->cellB : e->cellA];
}

static void edge_uv(const ts_edge *e, double t, double *u, double *v)
{
    double x = t <= 0.0 ? e->t0 : (t >= 1.0 ? e->t1 : e->t0 + t * (e->t1 - e->t0));
    if (e->dir == 0) {
        *u = x;
        *v = e->c;
    } else {
        *u = e->c;
        *v = x;
    }
}

static void edge_point(ts *T, const ts_edge *e, double t, double *out)
{
    double u, v;
    edge_uv(e, t, &u, &v);
    cell_point(T, edge_cell(T, e), u, v, out);
}

/* The warp of cell c's grid lines along dir (0: u), or NULL: uniform. */
static const double *cell_warp(const ts *T, const ts_cell *c, int dir)
{
    if (!T->warp_on)
        return NULL;
    const ts_surf *ss = &T->surf[c->surf];
    size_t k = dir == 0 ? c->a : c->b;
    if (!ss->won[dir] || !ss->won[dir][k])
        return NULL;
    return ss->wF[dir] + k * (WARP_N + 1);
}

/* Parameter at grid fraction f over [a, b] under warp F (exact ends). */
static double warp_t(const double *F, double a, double b, double f)
{
    if (f >= 1.0)
        return b;
    if (!(f > 0.0))
        return a;
    return a + geom__tess_warp_y(F, WARP_N, f) * (b - a);
}

/* ---------------------------------------------------------- union-find */

static uint32_t node_find(ts *T, uint32_t a) { return geom__uf_find(T->parent, a); }
static void node_union(ts *T, uint32_t a, uint32_t b) { geom__uf_union(T->parent, a, b); }

/* ------------------------------------------------------------ topology */

/* Cells, nodes (with their positions) and edges of every piece. */
static geom_status build_cells(ts *T, size_t ncells, size_t nnodes, size_t nedges)
{
    T->ncells = ncells;
    T->nnodes = nnodes;
    T->nedges = nedges;
    T->cells = ts_alloc(T, ncells, sizeof(ts_cell));
    T->nodes = ts_alloc(T, nnodes, sizeof(ts_node));
    T->parent = ts_alloc(T, nnodes, sizeof(uint32_t));
    T->edges = ts_alloc(T, nedges, sizeof(ts_edge));
    if (!T->cells || !T->nodes || !T->parent || !T->edges)
        return GEOM_ERR_NOMEM;
    memset(T->cells, 0, ncells * sizeof(ts_cell));
    memset(T->nodes, 0, nnodes * sizeof(ts_node));
    memset(T->edges, 0, nedges * sizeof(ts_edge));
    for (size_t k = 0; k < T->nsurf; ++k) {
        ts_surf *ss = &T->surf[k];
        size_t nbu = ss->nbu, nbv = ss->nbv;
        for (size_t a = 0; a < nbu; ++a)
            for (size_t b = 0; b < nbv; ++b) {
                ts_cell *c = &T->cells[ss->cell0 + a * nbv + b];
                c->surf = (uint32_t)k;
                c->a = (uint32_t)a;
                c->b = (uint32_t)b;
                c->u0 = ss->ub[a], c->u1 = ss->ub[a + 1];
                c->v0 = ss->vb[b], c->v1 = ss->vb[b + 1];
                c->ku = ss->ku[a];
                c->kv = ss->kv[b];
                c->eb = (uint32_t)(ss->uedge0 + b * nbu + a);
                c->et = (uint32_t)(ss->uedge0 + (b + 1) * nbu + a);
                c->el = (uint32_t)(ss->vedge0 + a * nbv + b);
                c->er = (uint32_t)(ss->vedge0 + (a + 1) * nbv + b);
            }
        for (size_t a = 0; a <= nbu; ++a)
            for (size_t b = 0; b <= nbv; ++b) {
                uint32_t id = (uint32_t)(ss->node0 + a * (nbv + 1) + b);
                ts_node *nd = &T->nodes[id];
                T->parent[id] = id;
                nd->vert = NONE32;
                nd->boundary = a == 0 || a == nbu || b == 0 || b == nbv;
                const ts_cell *c =
                    &T->cells[ss->cell0 + (a < nbu ? a : nbu - 1) * nbv + (b < nbv ? b : nbv - 1)];
                cell_point(T, c, ss->ub[a], ss->vb[b], nd->p);
            }
        for (size_t b = 0; b <= nbv; ++b)
            for (size_t a = 0; a < nbu; ++a) {
                ts_edge *e = &T->edges[ss->uedge0 + b * nbu + a];
                e->surf = (uint32_t)k;
                e->dir = 0;
                e->cellA = b > 0 ? (uint32_t)(ss->cell0 + a * nbv + b - 1) : NONE32;
                e->cellB = b < nbv ? (uint32_t)(ss->cell0 + a * nbv + b) : NONE32;
                e->n0 = (uint32_t)(ss->node0 + a * (nbv + 1) + b);
                e->n1 = (uint32_t)(ss->node0 + (a + 1) * (nbv + 1) + b);
                e->boundary = b == 0 || b == nbv;
                e->tau = b == 0 ? 1 : -1;
                e->c = ss->vb[b];
                e->t0 = ss->ub[a];
                e->t1 = ss->ub[a + 1];
                e->partner = NONE32;
            }
        for (size_t a = 0; a <= nbu; ++a)
            for (size_t b = 0; b < nbv; ++b) {
                ts_edge *e = &T->edges[ss->vedge0 + a * nbv + b];
                e->surf = (uint32_t)k;
                e->dir = 1;
                e->cellA = a > 0 ? (uint32_t)(ss->cell0 + (a - 1) * nbv + b) : NONE32;
                e->cellB = a < nbu ? (uint32_t)(ss->cell0 + a * nbv + b) : NONE32;
                e->n0 = (uint32_t)(ss->node0 + a * (nbv + 1) + b);
                e->n1 = (uint32_t)(ss->node0 + a * (nbv + 1) + b + 1);
                e->boundary = a == 0 || a == nbu;
                e->tau = a == 0 ? -1 : 1;
                e->c = ss->ub[a];
                e->t0 = ss->vb[b];
                e->t1 = ss->vb[b + 1];
                e->partner = NONE32;
            }
    }
    for (size_t i = 0; i < nedges; ++i)
        T->edges[i].owner = (uint32_t)i;
    return GEOM_OK;
}

/*
 * Non-empty spans of one direction: breaks b[0..nb], span index k[a] of
 * [b[a], b[a+1]], and disc[a] = 1 where break a (0 < a < nb) is a knot of
 * multiplicity > p (the surface is discontinuous there). Returns nb.
 */
static size_t dir_spans(int p, size_t n, const double *U, double *b, size_t *k, uint8_t *disc)
{
    size_t nb = 0;
    for (size_t i = (size_t)p; i < n; ++i)
        if (U[i] < U[i + 1]) {
            if (b) {
                b[nb] = U[i];
                k[nb] = i;
                b[nb + 1] = U[i + 1];
                size_t mult = 0;
                for (size_t j = 0; j < n + (size_t)p + 1; ++j)
                    mult += U[j] == U[i];
                disc[nb] = nb > 0 && mult > (size_t)p;
            }
            nb++;
        }
    return nb;
}

/*
 * Cut every surface into pieces at its discontinuities (knots of
 * multiplicity degree+1 inside the domain: each piece is continuous, and
 * pieces only meet through welding), then each piece into cells.
 */
static geom_status build_structure(ts *T, const geom_nurbs_surface *S, size_t n)
{
    const geom_surface_tess_options *o = T->opt;
    int per_surface = o->mode == GEOM_SURFACE_TESS_UNIFORM && o->per_surface;
    size_t maxb = 1, npieces = 0;
    for (size_t k = 0; k < n; ++k) {
        size_t a = dir_spans(S[k].degree_u, S[k].nu, S[k].knots_u, NULL, NULL, NULL);
        size_t b = dir_spans(S[k].degree_v, S[k].nv, S[k].knots_v, NULL, NULL, NULL);
        maxb = a > maxb ? a : maxb;
        maxb = b > maxb ? b : maxb;
    }
    double *bu = ts_alloc(T, maxb + 1, sizeof(double)), *bv = ts_alloc(T, maxb + 1, sizeof(double));
    size_t *kbu = ts_alloc(T, maxb, sizeof(size_t)), *kbv = ts_alloc(T, maxb, sizeof(size_t));
    uint8_t *du = ts_alloc(T, maxb, 1), *dv = ts_alloc(T, maxb, 1);
    geom_status st = GEOM_OK;
    if (!bu || !bv || !kbu || !kbv || !du || !dv) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    for (size_t k = 0; k < n; ++k) {
        size_t a = dir_spans(S[k].degree_u, S[k].nu, S[k].knots_u, bu, kbu, du);
        size_t b = dir_spans(S[k].degree_v, S[k].nv, S[k].knots_v, bv, kbv, dv);
        size_t pu = 1, pv = 1;
        for (size_t i = 1; i < a; ++i)
            pu += du[i];
        for (size_t j = 1; j < b; ++j)
            pv += dv[j];
        npieces += pu * pv;
    }
    if (npieces >= NONE32 / 8) {
        st = GEOM_ERR_LIMIT;
        goto done;
    }
    T->surf = ts_alloc(T, npieces, sizeof(ts_surf));
    if (!T->surf) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    memset(T->surf, 0, npieces * sizeof(ts_surf));
    T->nsurf = npieces;
    size_t ncells = 0, nnodes = 0, nedges = 0, piece = 0;
    for (size_t k = 0; k < n; ++k) {
        const geom_nurbs_surface *s = &S[k];
        size_t a = dir_spans(s->degree_u, s->nu, s->knots_u, bu, kbu, du);
        size_t b = dir_spans(s->degree_v, s->nv, s->knots_v, bv, kbv, dv);
        for (size_t a0 = 0; a0 < a;) {
            size_t a1 = a0 + 1;
            while (a1 < a && !du[a1])
                ++a1;
            for (size_t b0 = 0; b0 < b;) {
                size_t b1 = b0 + 1;
                while (b1 < b && !dv[b1])
                    ++b1;
                /* piece: spans a0..a1-1 by b0..b1-1 */
                ts_surf *ss = &T->surf[piece++];
                ss->s = s;
                ss->orig = (uint32_t)k;
                geom_surface_domain(s, ss->dom);
                size_t nbu = per_surface ? 1 : a1 - a0, nbv = per_surface ? 1 : b1 - b0;
                ss->nbu = nbu;
                ss->nbv = nbv;
                ss->ub = ts_alloc(T, nbu + 1, sizeof(double));
                ss->vb = ts_alloc(T, nbv + 1, sizeof(double));
                ss->ku = ts_alloc(T, nbu, sizeof(size_t));
                ss->kv = ts_alloc(T, nbv, sizeof(size_t));
                if (!ss->ub || !ss->vb || !ss->ku || !ss->kv) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
                if (per_surface) {
                    ss->ub[0] = bu[a0], ss->ub[1] = bu[a1];
                    ss->vb[0] = bv[b0], ss->vb[1] = bv[b1];
                    ss->ku[0] = ss->kv[0] = LOCATE;
                } else {
                    memcpy(ss->ub, bu + a0, (nbu + 1) * sizeof(double));
                    memcpy(ss->vb, bv + b0, (nbv + 1) * sizeof(double));
                    memcpy(ss->ku, kbu + a0, nbu * sizeof(size_t));
                    memcpy(ss->kv, kbv + b0, nbv * sizeof(size_t));
                }
                ss->cell0 = ncells;
                ss->node0 = nnodes;
                ss->uedge0 = nedges;
                ss->vedge0 = nedges + nbu * (nbv + 1);
                ncells += nbu * nbv;
                nnodes += (nbu + 1) * (nbv + 1);
                nedges += nbu * (nbv + 1) + (nbu + 1) * nbv;
                if (ncells >= NONE32 / 4 || nnodes >= NONE32 / 4 || nedges >= NONE32 / 4) {
                    st = GEOM_ERR_LIMIT;
                    goto done;
                }
                b0 = b1;
            }
            a0 = a1;
        }
    }
    st = build_cells(T, ncells, nnodes, nedges);
done:
    if (bu)
        ts_free(T, bu, maxb + 1, sizeof(double));
    if (bv)
        ts_free(T, bv, maxb + 1, sizeof(double));
    if (kbu)
        ts_free(T, kbu, maxb, sizeof(size_t));
    if (kbv)
        ts_free(T, kbv, maxb, sizeof(size_t));
    if (du)
        ts_free(T, du, maxb, 1);
    if (dv)
        ts_free(T, dv, maxb, 1);
    return st;
}

static int cmp_pos(const ts *T, uint32_t a, uint32_t b)
{
    const double *p = T->nodes[a].p, *q = T->nodes[b].p;
    for (int k = 0; k < 3; ++k) {
        if (p[k] < q[k])
            return -1;
        if (p[k] > q[k])
            return 1;
    }
    return 0;
}

/* Heap sort of n elements of `size` bytes under less(ctx, a, b), one for
 * the node ids and the edge keys (no qsort: it takes no context). */
typedef int (*heap_less_fn)(const void *ctx, const void *a, const void *b);

static void heap_swap(unsigned char *a, unsigned char *b, size_t size)
{
    for (size_t k = 0; k < size; ++k) {
        unsigned char t = a[k];
        a[k] = b[k];
        b[k] = t;
    }
}

static void heap_sift(unsigned char *v, size_t size, size_t i, size_t n, heap_less_fn less,
                      const void *ctx)
{
    for (;;) {
        size_t l = 2 * i + 1, m = i;
        if (l < n && less(ctx, v + m * size, v + l * size))
            m = l;
        if (l + 1 < n && less(ctx, v + m * size, v + (l + 1) * size))
            m = l + 1;
        if (m == i)
            return;
        heap_swap(v + i * size, v + m * size, size);
        i = m;
    }
}

static void heap_sort(void *base, size_t n, size_t size, heap_less_fn less, const void *ctx)
{
    unsigned char *v = base;
    for (size_t i = n / 2; i-- > 0;)
        heap_sift(v, size, i, n, less, ctx);
    for (size_t k = n; k-- > 1;) {
        heap_swap(v, v + k * size, size);
        heap_sift(v, size, 0, k, less, ctx);
    }
}

/* node ids by position */
static int node_less(const void *ctx, const void *a, const void *b)
{
    return cmp_pos(ctx, *(const uint32_t *)a, *(const uint32_t *)b) < 0;
}

typedef struct ekey {
    uint32_t lo, hi, id;
} ekey;

static int ekey_less(const void *ctx, const void *pa, const void *pb)
{
    const ekey *a = pa, *b = pb;
    (void)ctx;
    if (a->lo != b->lo)
        return a->lo < b->lo;
    if (a->hi != b->hi)
        return a->hi < b->hi;
    return a->id < b->id;
}

static const double probe_t[3] = {0.2113248654051871, 0.5, 0.7886751345948129};

/* Do e and o trace the same curve (o reversed if rev)? */
static int edges_coincide(ts *T, const ts_edge *e, const ts_edge *o, int rev)
{
    for (int k = 0; k < 3; ++k) {
        double p[3], q[3];
        edge_point(T, e, probe_t[k], p);
        edge_point(T, o, rev ? 1.0 - probe_t[k] : probe_t[k], q);
        if (!(dist3(p, q) <= T->weld_tol))
            return 0;
    }
    return 1;
}

static geom_status weld(ts *T, geom_surface_tess_stats *stats)
{
    /* collapsed edges: both ends and the probes at one point */
    for (size_t i = 0; i < T->nedges; ++i) {
        ts_edge *e = &T->edges[i];
        const double *p0 = T->nodes[e->n0].p;
        if (!(dist3(p0, T->nodes[e->n1].p) <= T->weld_tol))
            continue;
        int col = 1;
        for (int k = 0; k < 3 && col; ++k) {
            double p[3];
            edge_point(T, e, probe_t[k], p);
            col = dist3(p, p0) <= T->weld_tol;
        }
        if (col) {
            e->collapsed = 1;
            node_union(T, e->n0, e->n1);
            if (stats)
                stats->collapsed_edges++;
        }
    }
    if (T->opt->no_weld)
        return GEOM_OK;
    /* boundary nodes by exact position */
    size_t nb = 0;
    for (size_t i = 0; i < T->nnodes; ++i)
        nb += T->nodes[i].boundary;
    uint32_t *ids = ts_alloc(T, nb, sizeof(uint32_t));
    if (!ids)
        return GEOM_ERR_NOMEM;
    nb = 0;
    for (size_t i = 0; i < T->nnodes; ++i)
        if (T->nodes[i].boundary)
            ids[nb++] = (uint32_t)i;
    heap_sort(ids, nb, sizeof *ids, node_less, T);
    for (size_t i = 1; i < nb; ++i)
        if (cmp_pos(T, ids[i - 1], ids[i]) == 0)
            node_union(T, ids[i - 1], ids[i]);
    ts_free(T, ids, nb, sizeof(uint32_t));
    /* boundary edges with the same welded ends */
    size_t ne = 0;
    for (size_t i = 0; i < T->nedges; ++i)
        ne += T->edges[i].boundary && !T->edges[i].collapsed;
    ekey *keys = ts_alloc(T, ne, sizeof(ekey));
    if (!keys)
        return GEOM_ERR_NOMEM;
    ne = 0;
    for (size_t i = 0; i < T->nedges; ++i) {
        const ts_edge *e = &T->edges[i];
        if (!e->boundary || e->collapsed)
            continue;
        uint32_t a = node_find(T, e->n0), b = node_find(T, e->n1);
        keys[ne].lo = a < b ? a : b;
        keys[ne].hi = a < b ? b : a;
        keys[ne].id = (uint32_t)i;
        ne++;
    }
    heap_sort(keys, ne, sizeof *keys, ekey_less, NULL);
    for (size_t i = 0; i < ne;) {
        size_t j = i;
        while (j < ne && keys[j].lo == keys[i].lo && keys[j].hi == keys[i].hi)
            ++j;
        for (size_t x = i; x < j; ++x) {
            ts_edge *e = &T->edges[keys[x].id];
            if (e->partner != NONE32)
                continue;
            for (size_t y = x + 1; y < j; ++y) {
                ts_edge *o = &T->edges[keys[y].id];
                if (o->partner != NONE32)
                    continue;
                uint32_t e0 = node_find(T, e->n0), e1 = node_find(T, e->n1);
                uint32_t o0 = node_find(T, o->n0), o1 = node_find(T, o->n1);
                int rev = -1;
                if (e0 == o0 && e1 == o1 && edges_coincide(T, e, o, 0))
                    rev = 0;
                else if (e0 == o1 && e1 == o0 && edges_coincide(T, e, o, 1))
                    rev = 1;
                if (rev < 0)
                    continue;
                e->partner = keys[y].id;
                o->partner = keys[x].id;
                /* the lower id owns the samples */
                o->owner = keys[x].id;
                o->reversed = (uint8_t)rev;
                if (stats)
                    stats->welded_edges++;
                break;
            }
        }
        i = j;
    }
    ts_free(T, keys, ne, sizeof(ekey));
    return GEOM_OK;
}

/* Flip surfaces so that every welded edge is traversed in opposite
 * directions by its two cells (breadth-first over the welded pairs). */
static geom_status orient(ts *T, geom_surface_tess_stats *stats)
{
    if (T->opt->keep_orientation || T->opt->no_weld)
        return GEOM_OK;
    size_t n = T->nsurf;
    /* adjacency in CSR form over edge pairs */
    size_t *deg = ts_alloc(T, n + 1, sizeof(size_t));
    if (!deg)
        return GEOM_ERR_NOMEM;
    memset(deg, 0, (n + 1) * sizeof(size_t));
    size_t pairs = 0;
    for (size_t i = 0; i < T->nedges; ++i) {
        const ts_edge *e = &T->edges[i];
        if (e->partner != NONE32 && e->owner == i) {
            deg[e->surf]++;
            deg[T->edges[e->partner].surf]++;
            pairs++;
        }
    }
    size_t *start = ts_alloc(T, n + 1, sizeof(size_t));
    uint32_t *adj = ts_alloc(T, 2 * pairs, sizeof(uint32_t));
    uint8_t *rel = ts_alloc(T, 2 * pairs, 1);
    int8_t *state = ts_alloc(T, n, 1);
    uint32_t *queue = ts_alloc(T, n, sizeof(uint32_t));
    geom_status st = GEOM_OK;
    if (!start || !adj || !rel || !state || !queue) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    start[0] = 0;
    for (size_t k = 0; k < n; ++k)
        start[k + 1] = start[k] + deg[k];
    memset(deg, 0, (n + 1) * sizeof(size_t));
    for (size_t i = 0; i < T->nedges; ++i) {
        const ts_edge *e = &T->edges[i];
        if (e->partner == NONE32 || e->owner != i)
            continue;
        const ts_edge *o = &T->edges[e->partner];
        const ts_edge *ne = o; /* the non-owner holds the orientation */
        int sign = e->tau * ne->tau * (ne->reversed ? -1 : 1);
        uint8_t r = sign > 0; /* same traversal: one of them must flip */
        uint32_t a = e->surf, b = o->surf;
        adj[start[a] + deg[a]] = b;
        rel[start[a] + deg[a]++] = r;
        adj[start[b] + deg[b]] = a;
        rel[start[b] + deg[b]++] = r;
    }
    for (size_t k = 0; k < n; ++k)
        state[k] = -1;
    for (size_t k = 0; k < n; ++k) {
        if (state[k] >= 0)
            continue;
        state[k] = 0;
        size_t qh = 0, qt = 0;
        queue[qt++] = (uint32_t)k;
        while (qh < qt) {
            uint32_t a = queue[qh++];
            for (size_t x = start[a]; x < start[a + 1]; ++x) {
                uint32_t b = adj[x];
                int want = state[a] ^ rel[x];
                if (state[b] < 0) {
                    state[b] = (int8_t)want;
                    queue[qt++] = b;
                }
                /* a conflict (a non-orientable arrangement) keeps the
                 * first assignment */
            }
        }
    }
    for (size_t k = 0; k < n; ++k) {
        T->surf[k].flip = state[k] == 1;
        if (stats && state[k] == 1)
            stats->flipped_surfaces++;
    }
done:
    ts_free(T, deg, n + 1, sizeof(size_t));
    if (start)
        ts_free(T, start, n + 1, sizeof(size_t));
    if (adj)
        ts_free(T, adj, 2 * pairs, sizeof(uint32_t));
    if (rel)
        ts_free(T, rel, 2 * pairs, 1);
    if (state)
        ts_free(T, state, n, 1);
    if (queue)
        ts_free(T, queue, n, sizeof(uint32_t));
    return st;
}

/* --------------------------------------------------------------- sizing */

static uint32_t grid_count(double extent, double h)
{
    if (!(h > 0.0) || !isfinite(h))
        return 1;
    double m = ceil(extent / h - 1e-9);
    if (!(m >= 1.0))
        return 1;
    if (m > (double)MAX_GRID)
        return MAX_GRID + 1;
    return (uint32_t)m;
}

/*
 * Steps (hu, hv) that keep Muu hu^2 + 2 Muv hu hv + Mvv hv^2 <= B with the
 * largest quad area hu hv: the optimum has hu/hv = sqrt(Mvv/Muu). A zero
 * second derivative in one direction lets that step cover the whole cell.
 */
static void grid_steps(double B, double Muu, double Muv, double Mvv, double du, double dv,
                       double *hu, double *hv)
{
    if (Muu > 0.0 && Mvv > 0.0) {
        double r = sqrt(Mvv / Muu);
        double t = sqrt(B / (Muu * r * r + 2.0 * Muv * r + Mvv));
        *hu = r * t;
        *hv = t;
    } else if (Mvv > 0.0) { /* Muu == 0: one column, then hv from the quadratic */
        *hu = du;
        double b = Muv * du;
        *hv = (sqrt(b * b + B * Mvv) - b) / Mvv;
    } else if (Muu > 0.0) {
        *hv = dv;
        double b = Muv * dv;
        *hu = (sqrt(b * b + B * Muu) - b) / Muu;
    } else if (Muv > 0.0) {
        *hu = *hv = sqrt(B / (2.0 * Muv));
    } else {
        *hu = du;
        *hv = dv;
    }
}

/* Initial adaptive demand of a cell from sampled second derivatives. */
static void size_cell(ts *T, ts_cell *c)
{
    const geom_nurbs_surface *s = T->surf[c->surf].s;
    int pm = s->degree_u > s->degree_v ? s->degree_u : s->degree_v;
    int G = pm + 2;
    if (G < 4)
        G = 4;
    if (G > 9)
        G = 9;
    double Muu = 0.0, Muv = 0.0, Mvv = 0.0;
    double D[27];
    for (int i = 0; i < G; ++i)
        for (int j = 0; j < G; ++j) {
            double u = c->u0 + (c->u1 - c->u0) * (double)i / (double)(G - 1);
            double v = c->v0 + (c->v1 - c->v0) * (double)j / (double)(G - 1);
            if (i == G - 1)
                u = c->u1;
            if (j == G - 1)
                v = c->v1;
            cell_derivs(T, c, u, v, 2, D);
            /* d = 2: (k,l) at 3*(3k + l) */
            double x = sqrt(D[18] * D[18] + D[19] * D[19] + D[20] * D[20]);
            double y = sqrt(D[12] * D[12] + D[13] * D[13] + D[14] * D[14]);
            double z = sqrt(D[6] * D[6] + D[7] * D[7] + D[8] * D[8]);
            if (isfinite(x))
                Muu = fmax(Muu, x);
            if (isfinite(y))
                Muv = fmax(Muv, y);
            if (isfinite(z))
                Mvv = fmax(Mvv, z);
        }
    double du = c->u1 - c->u0, dv = c->v1 - c->v0;
    double hu, hv;
    grid_steps(8.0 * T->tol, Muu, Muv, Mvv, du, dv, &hu, &hv);
    c->M = grid_count(du, hu);
    c->N = grid_count(dv, hv);
}

/*
 * Grid-line warps (tess_warp.c): per cell column of a piece, the lines of
 * constant u are placed where sqrt(k) has equal integrals, k the largest
 * |S_uu normal to S_u| over the column (sampled at 4 values of v per
 * cell), so that rational weights that make the parametric speed vary
 * across a cell (the chord error with it) do not force the whole cell's
 * grid to the step of its fastest part. Rows likewise along v. A column
 * and its cells' edges share one warp, so neighbouring cells keep using
 * the very same edge samples; welded edges must have the same warp as
 * their partner (reversed where they run the other way), else both
 * columns keep uniform lines.
 */
static double warp_density(ts *T, const ts_surf *ss, int dir, size_t k, double y)
{
    size_t nacross = dir == 0 ? ss->nbv : ss->nbu;
    double t = dir == 0 ? ss->ub[k] + y * (ss->ub[k + 1] - ss->ub[k])
                        : ss->vb[k] + y * (ss->vb[k + 1] - ss->vb[k]);
    double kmax = 0.0, D[27];
    for (size_t o = 0; o < nacross; ++o) {
        const ts_cell *c =
            &T->cells[ss->cell0 + (dir == 0 ? k * ss->nbv + o : o * ss->nbv + k)];
        for (int q = 0; q < 4; ++q) {
            double x = (q + 0.5) / 4.0;
            double u = dir == 0 ? t : c->u0 + x * (c->u1 - c->u0);
            double v = dir == 0 ? c->v0 + x * (c->v1 - c->v0) : t;
            cell_derivs(T, c, u, v, 2, D);
            /* d = 2: (k,l) at 3*(3k + l) */
            const double *d1 = dir == 0 ? D + 9 : D + 3, *d2 = dir == 0 ? D + 18 : D + 6;
            double n1 = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
            if (!(n1 > 0.0) || !isfinite(n1))
                continue; /* degenerate (a pole): no tangent */
            double a = (d2[0] * d1[0] + d2[1] * d1[1] + d2[2] * d1[2]) / n1, r[3];
            for (int e = 0; e < 3; ++e)
                r[e] = d2[e] - a * d1[e];
            double h = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            if (isfinite(h))
                kmax = fmax(kmax, h);
        }
    }
    return sqrt(kmax);
}

/* Do edges e and its partner p see the same warp (as fractions)? */
static int warps_agree(const ts *T, const ts_edge *e, const ts_edge *p)
{
    const double *Fe = cell_warp(T, edge_cell(T, e), e->dir);
    const double *Fp = cell_warp(T, edge_cell(T, p), p->dir);
    if (!Fe && !Fp)
        return 1;
    int rev = e->reversed || p->reversed;
    for (int i = 1; i < 64; ++i) {
        double f = (double)i / 64.0;
        double ye = Fe ? geom__tess_warp_y(Fe, WARP_N, f) : f;
        double yp = Fp ? geom__tess_warp_y(Fp, WARP_N, rev ? 1.0 - f : f) : (rev ? 1.0 - f : f);
        if (!(fabs(ye - (rev ? 1.0 - yp : yp)) <= 1e-12))
            return 0;
    }
    return 1;
}

static void warp_off(const ts *T, const ts_edge *e)
{
    const ts_cell *c = edge_cell(T, e);
    T->surf[c->surf].won[e->dir][e->dir == 0 ? c->a : c->b] = 0;
}

static geom_status build_warps(ts *T)
{
    double rho[WARP_N];
    for (size_t k = 0; k < T->nsurf; ++k) {
        ts_surf *ss = &T->surf[k];
        for (int d = 0; d < 2; ++d) {
            size_t nb = d ? ss->nbv : ss->nbu;
            ss->wF[d] = ts_alloc(T, nb * (WARP_N + 1), sizeof(double));
            ss->won[d] = ts_alloc(T, nb, 1);
            if (!ss->wF[d] || !ss->won[d])
                return GEOM_ERR_NOMEM;
            for (size_t a = 0; a < nb; ++a) {
                for (int i = 0; i < WARP_N; ++i)
                    rho[i] = warp_density(T, ss, d, a, (i + 0.5) / WARP_N);
                ss->won[d][a] = (uint8_t)geom__tess_warp_build(rho, WARP_N, WARP_RATIO, WARP_FLOOR,
                                                              ss->wF[d] + a * (WARP_N + 1));
            }
        }
    }
    T->warp_on = 1;
    /* welded edges: both sides' warps agree, else both uniform */
    for (int changed = 1; changed;) {
        changed = 0;
        for (size_t i = 0; i < T->nedges; ++i) {
            const ts_edge *e = &T->edges[i];
            if (e->partner == NONE32 || e->collapsed)
                continue;
            const ts_edge *p = &T->edges[e->partner];
            if (!warps_agree(T, e, p)) {
                warp_off(T, e);
                warp_off(T, p);
                changed = 1;
            }
        }
    }
    return GEOM_OK;
}

/* ---------------------------------------------------- per-pass vertices */

static geom_status add_vertex(ts *T, const double *p, uint32_t *id)
{
    if (T->nverts >= NONE32 - 1)
        return GEOM_ERR_LIMIT;
    geom_status st =
        geom__grow(T->alloc, (void **)&T->pos, &T->cap_verts, 3 * (T->nverts + 1), sizeof(double));
    if (st != GEOM_OK)
        return st;
    if (p)
        memcpy(T->pos + 3 * T->nverts, p, 3 * sizeof(double));
    *id = (uint32_t)T->nverts++;
    return GEOM_OK;
}

static uint32_t edge_demand(const ts *T, const ts_edge *e)
{
    uint32_t d = 1;
    const uint32_t cs[2] = {e->cellA, e->cellB};
    for (int k = 0; k < 2; ++k)
        if (cs[k] != NONE32) {
            const ts_cell *c = &T->cells[cs[k]];
            uint32_t x = e->dir == 0 ? c->M : c->N;
            if (x > d)
                d = x;
        }
    return d;
}

/* Edge sample counts, vertex ids and positions of nodes and edge samples. */
static geom_status assign_vertices(ts *T)
{
    T->nverts = 0;
    for (size_t i = 0; i < T->nnodes; ++i)
        T->nodes[i].vert = NONE32;
    geom_status st;
    for (size_t i = 0; i < T->nnodes; ++i) {
        uint32_t r = node_find(T, (uint32_t)i);
        if (T->nodes[r].vert == NONE32) {
            st = add_vertex(T, T->nodes[r].p, &T->nodes[r].vert);
            if (st != GEOM_OK)
                return st;
        }
    }
    for (size_t i = 0; i < T->nedges; ++i) {
        ts_edge *e = &T->edges[i];
        if (e->owner != i)
            continue;
        uint32_t d = edge_demand(T, e);
        if (e->partner != NONE32) {
            uint32_t d2 = edge_demand(T, &T->edges[e->partner]);
            if (d2 > d)
                d = d2;
        }
        e->nseg = d;
        if (e->partner != NONE32)
            T->edges[e->partner].nseg = d;
        if (e->collapsed || d < 2)
            continue;
        e->vbase = (uint32_t)T->nverts;
        const double *F = cell_warp(T, edge_cell(T, e), e->dir);
        for (uint32_t k = 1; k < d; ++k) {
            double p[3], f = (double)k / (double)d;
            edge_point(T, e, F ? geom__tess_warp_y(F, WARP_N, f) : f, p);
            uint32_t id;
            st = add_vertex(T, p, &id);
            if (st != GEOM_OK)
                return st;
        }
    }
    return GEOM_OK;
}

static uint32_t edge_vertex(ts *T, const ts_edge *e, uint32_t k)
{
    if (e->collapsed)
        return T->nodes[node_find(T, e->n0)].vert;
    if (k == 0)
        return T->nodes[node_find(T, e->n0)].vert;
    if (k == e->nseg)
        return T->nodes[node_find(T, e->n1)].vert;
    const ts_edge *o = &T->edges[e->owner];
    uint32_t kk = (e->owner != (uint32_t)(e - T->edges) && e->reversed) ? e->nseg - k : k;
    return o->vbase + kk - 1;
}

/* ----------------------------------------------------- cell triangulation */

/* Side of triangle L (0: L1L2, 1: L0L2, 2: L0L1) shared with triangle M
 * (local or grid corner ids): the one opposite L's corner not in M. */
static int shared_side(const uint32_t *L, const uint32_t *M)
{
    int side = -1, out = 0;
    for (int k = 0; k < 3; ++k)
        if (L[k] != M[0] && L[k] != M[1] && L[k] != M[2])
            side = k, out++;
    return out == 1 ? side : -1;
}

static geom_status local_add(ts *T, double u, double v, uint32_t vert, uint32_t *idx)
{
    size_t need = T->nloc + 1;
    if (need > T->cap_lnorm) { /* grown last: the four arrays hold need when it does */
        geom_status st = geom__grow(T->alloc, (void **)&T->lu, &T->cap_lu, need, sizeof(double));
        if (st == GEOM_OK)
            st = geom__grow(T->alloc, (void **)&T->lv, &T->cap_lv, need, sizeof(double));
        if (st == GEOM_OK)
            st = geom__grow(T->alloc, (void **)&T->lvert, &T->cap_lvert, need, sizeof(uint32_t));
        if (st == GEOM_OK)
            st = geom__grow(T->alloc, (void **)&T->lnorm, &T->cap_lnorm, need, 6 * sizeof(double));
        if (st != GEOM_OK)
            return st;
    }
    T->lu[T->nloc] = u;
    T->lv[T->nloc] = v;
    T->lvert[T->nloc] = vert;
    *idx = (uint32_t)T->nloc++;
    return GEOM_OK;
}

static geom_status local_tri(ts *T, uint32_t a, uint32_t b, uint32_t c)
{
    if (T->lvert[a] == T->lvert[b] || T->lvert[b] == T->lvert[c] || T->lvert[a] == T->lvert[c])
        return GEOM_OK; /* on a collapsed edge */
    geom_status st = geom__grow(T->alloc, (void **)&T->ltri, &T->cap_ltri, 3 * (T->nltri + 1),
                             sizeof(uint32_t));
    if (st == GEOM_OK)
        st = geom__grow(T->alloc, (void **)&T->lmate, &T->cap_lmate, 2 * (T->nltri + 1),
                        sizeof(uint32_t));
    if (st == GEOM_OK)
        st = geom__grow(T->alloc, (void **)&T->ldiag, &T->cap_ldiag, T->nltri + 1, 1);
    if (st != GEOM_OK)
        return st;
    T->lmate[2 * T->nltri] = T->lmate[2 * T->nltri + 1] = NONE32;
    T->ldiag[T->nltri] = 0;
    T->ltri[3 * T->nltri] = a;
    T->ltri[3 * T->nltri + 1] = b;
    T->ltri[3 * T->nltri + 2] = c;
    T->nltri++;
    return GEOM_OK;
}

/* Does a quad with diagonals ac and bd split along ac? Along the shorter
 * diagonal; a near tie (bd shorter by at most 8 weld tolerances, as every
 * quad of a surface of revolution between two meridians is a tie in exact
 * arithmetic) takes ac, so that the choice does not hang on the last bits
 * of the positions (see uniform_search). */
static int split_ac(const ts *T, double ac, double bd)
{
    return ac <= bd + 8.0 * T->weld_tol;
}

/* Quad a b c d (counter-clockwise) as two triangles along the shorter
 * diagonal (split_ac). */
static geom_status local_quad(ts *T, uint32_t a, uint32_t b, uint32_t c, uint32_t d)
{
    double ac = dist3(T->pos + 3 * (size_t)T->lvert[a], T->pos + 3 * (size_t)T->lvert[c]);
    double bd = dist3(T->pos + 3 * (size_t)T->lvert[b], T->pos + 3 * (size_t)T->lvert[d]);
    geom_status st;
    size_t t0 = T->nltri, t1;
    int sac = split_ac(T, ac, bd);
    /* the diagonal is side 1 (X0X2) of a b c, 2 (X0X1) of a c d, 0 (X1X2)
     * of a b d and 1 of b c d */
    if (sac) {
        st = local_tri(T, a, b, c);
        t1 = T->nltri;
        if (st == GEOM_OK && t1 > t0)
            T->ldiag[t0] = 2;
        if (st == GEOM_OK)
            st = local_tri(T, a, c, d);
        if (st == GEOM_OK && T->nltri > t1)
            T->ldiag[t1] = 4;
    } else {
        st = local_tri(T, a, b, d);
        t1 = T->nltri;
        if (st == GEOM_OK && t1 > t0)
            T->ldiag[t0] = 1;
        if (st == GEOM_OK)
            st = local_tri(T, b, c, d);
        if (st == GEOM_OK && T->nltri > t1)
            T->ldiag[t1] = 2;
    }
    if (st == GEOM_OK && T->nltri == t0 + 2) {
        T->lmate[2 * t0] = (uint32_t)t0 + 1;
        T->lmate[2 * (t0 + 1)] = (uint32_t)t0;
    }
    return st;
}

/* Join the outer polyline o (no points, fractions fo) to the inner one i
 * (ni points, fi), both running in the cell's counter-clockwise direction
 * with the cell's inside to their left. */
static geom_status stitch(ts *T, const uint32_t *o, const double *fo, size_t no, const uint32_t *in,
                          const double *fi, size_t ni)
{
    size_t a = 0, b = 0, prev = SIZE_MAX;
    while (a + 1 < no || b + 1 < ni) {
        int outer;
        if (a + 1 >= no)
            outer = 0;
        else if (b + 1 >= ni)
            outer = 1;
        else
            outer = fo[a + 1] <= fi[b + 1];
        geom_status st;
        size_t t = T->nltri;
        if (outer) {
            st = local_tri(T, o[a], o[a + 1], in[b]);
            ++a;
        } else {
            st = local_tri(T, o[a], in[b + 1], in[b]);
            ++b;
        }
        if (st != GEOM_OK)
            return st;
        if (T->nltri == t) { /* dropped at a pole: the chain breaks */
            prev = SIZE_MAX;
            continue;
        }
        /* consecutive triangles of a strip share the rung between them */
        if (prev != SIZE_MAX) {
            int sp = shared_side(T->ltri + 3 * prev, T->ltri + 3 * t);
            int st2 = shared_side(T->ltri + 3 * t, T->ltri + 3 * prev);
            if (sp >= 0 && st2 >= 0) {
                T->lmate[2 * prev + 1] = (uint32_t)t;
                T->lmate[2 * t] = (uint32_t)prev;
                T->ldiag[prev] |= (uint8_t)(1u << sp);
                T->ldiag[t] |= (uint8_t)(1u << st2);
            }
        }
        prev = t;
    }
    return GEOM_OK;
}

/* Samples and triangles of cell c into the local arrays; interior vertex
 * positions into T->pos (ids from c->vbase). */
static geom_status triangulate_cell(ts *T, ts_cell *c)
{
    T->nloc = 0;
    T->nltri = 0;
    const ts_edge *E[4] = {&T->edges[c->eb], &T->edges[c->er], &T->edges[c->et],
                           &T->edges[c->el]};
    uint32_t nb = E[0]->nseg, nr = E[1]->nseg, nt = E[2]->nseg, nl = E[3]->nseg;
    uint32_t M = c->M, N = c->N;
    int direct = nb == M && nt == M && nl == N && nr == N;
    if (!direct) {
        if (M < 2)
            M = 2;
        if (N < 2)
            N = 2;
    }
    c->sig[0] = M, c->sig[1] = N, c->sig[2] = nb, c->sig[3] = nr, c->sig[4] = nt, c->sig[5] = nl;
    double du = c->u1 - c->u0, dv = c->v1 - c->v0;
    const double *Fu = cell_warp(T, c, 0), *Fv = cell_warp(T, c, 1);
    /* edge samples, each in its own parameter direction */
    uint32_t first[4];
    const uint32_t cnt[4] = {nb, nr, nt, nl};
    geom_status st = GEOM_OK;
    for (int k = 0; k < 4; ++k) {
        first[k] = (uint32_t)T->nloc;
        for (uint32_t i = 0; i <= cnt[k]; ++i) {
            double f = (double)i / (double)cnt[k];
            double u, v;
            if (k == 0 || k == 2) {
                u = Fu ? warp_t(Fu, c->u0, c->u1, f) : i == cnt[k] ? c->u1 : c->u0 + f * du;
                v = k == 0 ? c->v0 : c->v1;
            } else {
                v = Fv ? warp_t(Fv, c->v0, c->v1, f) : i == cnt[k] ? c->v1 : c->v0 + f * dv;
                u = k == 3 ? c->u0 : c->u1;
            }
            uint32_t idx;
            st = local_add(T, u, v, edge_vertex(T, E[k], i), &idx);
            if (st != GEOM_OK)
                return st;
        }
    }
    /* interior grid (i, j), 1 <= i <= M-1, 1 <= j <= N-1 */
    uint32_t gfirst = (uint32_t)T->nloc;
    c->vbase = (uint32_t)T->nverts;
    for (uint32_t i = 1; i < M; ++i)
        for (uint32_t j = 1; j < N; ++j) {
            double u = Fu ? warp_t(Fu, c->u0, c->u1, (double)i / (double)M)
                          : c->u0 + du * (double)i / (double)M;
            double v = Fv ? warp_t(Fv, c->v0, c->v1, (double)j / (double)N)
                          : c->v0 + dv * (double)j / (double)N;
            double p[3];
            cell_point(T, c, u, v, p);
            uint32_t vid, idx;
            st = add_vertex(T, p, &vid);
            if (st == GEOM_OK)
                st = local_add(T, u, v, vid, &idx);
            if (st != GEOM_OK)
                return st;
        }
#define G(i, j) (gfirst + ((i)-1) * (N - 1) + ((j)-1))
    if (direct) {
        for (uint32_t i = 0; i < M; ++i)
            for (uint32_t j = 0; j < N; ++j) {
                uint32_t q[4];
                const uint32_t ii[4] = {i, i + 1, i + 1, i}, jj[4] = {j, j, j + 1, j + 1};
                for (int k = 0; k < 4; ++k) {
                    uint32_t x = ii[k], y = jj[k];
                    if (y == 0)
                        q[k] = first[0] + x;
                    else if (y == N)
                        q[k] = first[2] + x;
                    else if (x == 0)
                        q[k] = first[3] + y;
                    else if (x == M)
                        q[k] = first[1] + y;
                    else
                        q[k] = G(x, y);
                }
                st = local_quad(T, q[0], q[1], q[2], q[3]);
                if (st != GEOM_OK)
                    return st;
            }
        return GEOM_OK;
    }
    for (uint32_t i = 1; i + 1 < M; ++i)
        for (uint32_t j = 1; j + 1 < N; ++j) {
            st = local_quad(T, G(i, j), G(i + 1, j), G(i + 1, j + 1), G(i, j + 1));
            if (st != GEOM_OK)
                return st;
        }
    /* the ring: four strips, counter-clockwise */
    uint32_t cap = (nb > nr ? nb : nr);
    cap = cap > nt ? cap : nt;
    cap = cap > nl ? cap : nl;
    cap = (cap > M ? cap : M);
    cap = (cap > N ? cap : N) + 2;
    uint32_t *oi = ts_alloc(T, 2 * (size_t)cap, sizeof(uint32_t));
    double *of = ts_alloc(T, 2 * (size_t)cap, sizeof(double));
    if (!oi || !of) {
        if (oi)
            ts_free(T, oi, 2 * (size_t)cap, sizeof(uint32_t));
        if (of)
            ts_free(T, of, 2 * (size_t)cap, sizeof(double));
        return GEOM_ERR_NOMEM;
    }
    uint32_t *ii = oi + cap;
    double *fi = of + cap;
    for (int side = 0; side < 4 && st == GEOM_OK; ++side) {
        uint32_t n = cnt[side];
        size_t no = 0, ni = 0;
        for (uint32_t k = 0; k <= n; ++k) {
            uint32_t kk = side < 2 ? k : n - k; /* top and left run backwards */
            oi[no] = first[side] + kk;
            of[no++] = (double)k / (double)n;
        }
        if (side == 0)
            for (uint32_t i = 1; i < M; ++i)
                ii[ni] = G(i, 1), fi[ni++] = (double)i / (double)M;
        else if (side == 1)
            for (uint32_t j = 1; j < N; ++j)
                ii[ni] = G(M - 1, j), fi[ni++] = (double)j / (double)N;
        else if (side == 2)
            for (uint32_t i = M - 1; i >= 1; --i)
                ii[ni] = G(i, N - 1), fi[ni++] = 1.0 - (double)i / (double)M;
        else
            for (uint32_t j = N - 1; j >= 1; --j)
                ii[ni] = G(1, j), fi[ni++] = 1.0 - (double)j / (double)N;
        st = stitch(T, oi, of, no, ii, fi, ni);
    }
#undef G
    ts_free(T, oi, 2 * (size_t)cap, sizeof(uint32_t));
    ts_free(T, of, 2 * (size_t)cap, sizeof(double));
    return st;
}

/* ---------------------------------------------------------------- checks */

static double angle_between(const double *a, const double *b)
{
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                   a[0] * b[1] - a[1] * b[0]};
    double s = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return atan2(s, d) * (180.0 / GEOM_PI);
}

/* Largest sampled chordal error of one triangle of cell c (corners X with
 * parameters U, V). The surface is sampled at the K-lattice points of the
 * triangle's parameter-space image, S(sum b_i (u_i, v_i)) for b_i = k_i/K,
 * other than the corners, and each sample's error is its distance to the
 * mesh there: to the nearest of the 3D triangle and its ny neighbours
 * across its inner sides (Y: 3 corners each; a grid quad's other half, a
 * strip triangle's neighbours in the strip), since the image of a
 * parameter-space diagonal or rung is no straight line. Bit s of `inner`
 * marks side s (0 X1X2, 1 X0X2, 2 X0X1) as inner (a quad's diagonal, also
 * when its other half was dropped at a pole; a strip's rungs); samples on
 * the other sides (the quad's or strip's outer
 * sides, which lie on grid lines or cell edges) are measured to that side
 * only, so that mesh edges follow the surface's curves there. This is a
 * one-sided Hausdorff distance at the samples, never larger than the
 * distance to the triangle's point at the same barycentric combination
 * (taken as the minimum with it, so rounding cannot make it larger).
 *
 * Fold guard: the images of the lattice's small triangles (counter-
 * clockwise in parameter space, like the triangle) must not face against
 * the triangle's normal. Where one does, the surface turns back over the
 * triangle, which a distance to the mesh would not see; the triangle's
 * error is then the equal-parameter distance at every sample.
 *
 * The worst sample's parameters go to *wu, *wv (when it is over 0). */
#define LI(i, j) (3 * ((size_t)(i) * (2 * (size_t)K + 3 - (size_t)(i)) / 2 + (size_t)(j)))

/* The lattice samples of tri_error into T->lat. */
static void tri_lattice(ts *T, const ts_cell *c, const double *const X[3], const double *U,
                        const double *V)
{
    int K = T->ksub;
    double *S = T->lat;
    for (int i = 0; i <= K; ++i)
        for (int j = 0; i + j <= K; ++j) {
            int k = K - i - j;
            double *p = S + LI(i, j);
            const double *corner = i == K ? X[0] : j == K ? X[1] : k == K ? X[2] : NULL;
            if (corner) {
                p[0] = corner[0], p[1] = corner[1], p[2] = corner[2];
                continue;
            }
            double b0 = (double)i / K, b1 = (double)j / K, b2 = (double)k / K;
            double u = b0 * U[0] + b1 * U[1] + b2 * U[2], v = b0 * V[0] + b1 * V[1] + b2 * V[2];
            if (!T->memo_on) {
                cell_point(T, c, u, v, p);
                continue;
            }
            uint64_t bu, bv;
            memcpy(&bu, &u, sizeof bu);
            memcpy(&bv, &v, sizeof bv);
            uint64_t h = (bu * 0x9e3779b97f4a7c15ull) ^ (bv * 0xc2b2ae3d27d4eb4full);
            ts_memo *m = &T->memo[(h ^ (h >> 29)) >> (64 - MEMO_BITS)];
            if (m->gen == T->memo_gen && memcmp(&m->u, &u, sizeof u) == 0 &&
                memcmp(&m->v, &v, sizeof v) == 0) {
                p[0] = m->p[0], p[1] = m->p[1], p[2] = m->p[2];
                continue;
            }
            cell_point(T, c, u, v, p);
            m->u = u, m->v = v, m->gen = T->memo_gen;
            m->p[0] = p[0], m->p[1] = p[1], m->p[2] = p[2];
        }
}

/* tri_error on the lattice samples already in T->lat. */
static double tri_error_lat(ts *T, const double *const X[3], const double *U, const double *V,
                            const double *const *Y, int ny, unsigned inner, double *wu,
                            double *wv)
{
    int K = T->ksub;
    const double *S = T->lat;
    /* fold guard */
    double e1[3], e2[3], nt[3];
    for (int d = 0; d < 3; ++d)
        e1[d] = X[1][d] - X[0][d], e2[d] = X[2][d] - X[0][d];
    cross3(e1, e2, nt);
    double ntl = sqrt(nt[0] * nt[0] + nt[1] * nt[1] + nt[2] * nt[2]);
    int folded = 0;
    if (ntl > 0.0 && isfinite(ntl))
        for (int i = 0; i < K && !folded; ++i)
            for (int j = 0; i + j < K && !folded; ++j)
                for (int up = 0; up < 2 && !folded; ++up) {
                    if (up == 1 && i + j + 2 > K)
                        break;
                    const double *A = up ? S + LI(i + 1, j) : S + LI(i, j);
                    const double *B = up ? S + LI(i + 1, j + 1) : S + LI(i + 1, j);
                    const double *C = S + LI(i, j + 1);
                    double a[3], b[3], ns[3];
                    for (int d = 0; d < 3; ++d)
                        a[d] = B[d] - A[d], b[d] = C[d] - A[d];
                    cross3(a, b, ns);
                    double dot = ns[0] * nt[0] + ns[1] * nt[1] + ns[2] * nt[2];
                    if (!(dot < 0.0))
                        continue; /* cannot be below -1e-3 |ns| |nt| <= 0 */
                    double nsl = sqrt(ns[0] * ns[0] + ns[1] * ns[1] + ns[2] * ns[2]);
                    folded = dot < -1e-3 * nsl * ntl;
                }
    double tmax = 0.0;
    for (int i = 0; i <= K; ++i)
        for (int j = 0; i + j <= K; ++j) {
            int k = K - i - j;
            if (i == K || j == K || k == K)
                continue;
            double b0 = (double)i / K, b1 = (double)j / K, b2 = (double)k / K;
            const double *P = S + LI(i, j);
            /* e = min(equal-parameter distance, distance to the mesh); the
             * parts that cannot raise tmax are skipped (the same tmax) */
            double e = NAN;
            if (!folded) {
                int side = i == 0 ? 0 : j == 0 ? 1 : k == 0 ? 2 : -1;
                if (side == 0 && !(inner & 1u))
                    e = sqrt(geom__closest_seg_d2(P, X[1], X[2]));
                else if (side == 1 && !(inner & 2u))
                    e = sqrt(geom__closest_seg_d2(P, X[0], X[2]));
                else if (side == 2 && !(inner & 4u))
                    e = sqrt(geom__closest_seg_d2(P, X[0], X[1]));
                else {
                    double h = geom__closest_tri_d2(P, X[0], X[1], X[2]);
                    for (int q = 0; q < ny && !(sqrt(h) <= tmax); ++q)
                        h = fmin(h, geom__closest_tri_d2(P, Y[3 * q], Y[3 * q + 1], Y[3 * q + 2]));
                    e = sqrt(h);
                }
            }
            if (!(e <= tmax)) {
                double L3[3];
                for (int d = 0; d < 3; ++d)
                    L3[d] = b0 * X[0][d] + b1 * X[1][d] + b2 * X[2][d];
                e = fmin(dist3(L3, P), e);
            }
            if (e > tmax) {
                tmax = e;
                *wu = b0 * U[0] + b1 * U[1] + b2 * U[2];
                *wv = b0 * V[0] + b1 * V[1] + b2 * V[2];
            }
        }
    return tmax;
}

static double tri_error(ts *T, const ts_cell *c, const double *const X[3], const double *U,
                        const double *V, const double *const *Y, int ny, unsigned inner,
                        double *wu, double *wv)
{
    tri_lattice(T, c, X, U, V);
    return tri_error_lat(T, X, U, V, Y, ny, inner, wu, wv);
}


/* Chordal error (and normal angle) of the cell's local triangles. */
static void check_cell(ts *T, ts_cell *c)
{
    /* samples are shared within this check only (a point depends on the
     * cell through its spans) */
    if (T->memo && ++T->memo_gen == 0) {
        memset(T->memo, 0, MEMO_SIZE * sizeof(ts_memo));
        T->memo_gen = 1;
    }
    T->memo_on = T->memo != NULL;
    double cell_max = 0.0, ang_max = 0.0, esum = 0.0;
    if (T->ang_tol > 0.0)
        for (size_t k = 0; k < T->nloc; ++k)
            cell_normal(T, c, T->lu[k], T->lv[k], T->lnorm + 6 * k, T->lnorm + 6 * k + 3);
    c->wu = 0.5 * (c->u0 + c->u1);
    c->wv = 0.5 * (c->v0 + c->v1);
    for (size_t t = 0; t < T->nltri; ++t) {
        const uint32_t *L = T->ltri + 3 * t;
        const double *X[3];
        double U[3], V[3], wu = 0.0, wv = 0.0;
        for (int k = 0; k < 3; ++k) {
            X[k] = T->pos + 3 * (size_t)T->lvert[L[k]];
            U[k] = T->lu[L[k]];
            V[k] = T->lv[L[k]];
        }
        const double *Y[6];
        int ny = 0;
        for (int q = 0; q < 2; ++q) {
            uint32_t nb = T->lmate[2 * t + (size_t)q];
            if (nb == NONE32)
                continue;
            const uint32_t *M = T->ltri + 3 * (size_t)nb;
            for (int k = 0; k < 3; ++k)
                Y[3 * ny + k] = T->pos + 3 * (size_t)T->lvert[M[k]];
            ny++;
        }
        double tmax = tri_error(T, c, X, U, V, Y, ny, T->ldiag[t], &wu, &wv);
        if (tmax > cell_max) {
            cell_max = tmax;
            c->wu = wu;
            c->wv = wv;
        }
        esum += (tmax - esum) / (double)(t + 1); /* running mean: finite near DBL_MAX */
        if (T->ang_tol > 0.0) {
            for (int a = 0; a < 3; ++a)
                for (int b = a + 1; b < 3; ++b) {
                    double g = angle_between(T->lnorm + 6 * (size_t)L[a], T->lnorm + 6 * (size_t)L[b]);
                    if (g > ang_max)
                        ang_max = g;
                }
        }
    }
    T->memo_on = 0;
    c->err = cell_max;
    c->ang = ang_max;
    c->esum = esum;
    c->ecnt = T->nltri;
    c->checked = 1;
}

/* ----------------------------------------------------- grid choice per cell */

/*
 * After the adaptive passes converge, each cell's grid is replaced by the
 * M x N grid with the fewest quads whose triangles pass the same sampled
 * check (when one is smaller). The passes scale a cell's grid in both
 * directions by one factor from the second-derivative bound, so its aspect
 * ratio is the bound's, not the best one: on the NURBS sphere the grid
 * came out 28x28 per span at 1e-3 where 24x31 passes with 5% fewer
 * triangles, and a uniform grid then needed fewer triangles than adaptive.
 * Since a uniform u x v grid is one choice of every cell's grid, taking each
 * cell's smallest passing grid never needs more quads than it.
 *
 * The search walks the staircase of smallest passing N per M: for each M
 * from a lower bound up, only the largest N that would beat the best
 * product so far is tried (a larger error is assumed at every smaller N),
 * and the N of a passing grid is lowered while it passes. A grid that fails
 * usually fails at once: the quads around the cell's worst point are
 * checked first. Lower bounds: a grid holds the cell's boundary lines, so M
 * is at least the smallest segment count along the two lines of constant v
 * whose chords pass the same sampled check (N likewise).
 *
 * Every passing check evaluates the whole grid, and a walk from a guess
 * passes once per improvement it finds (the sphere's spans at 1e-4: five
 * times, each about the final grid's cost). Congruent cells (the sphere's
 * spans, the teapot's mirrored patches) start their walks alike (the same
 * first column and boundary-line bounds), so the last 16 answers are kept
 * by that start and a cell starting as one of them did tries its answer
 * first; when it passes, the other columns' tries have a smaller product
 * and usually fail at their first quads. With a grid's passing assumed
 * monotone in N (as the bisection assumes), the walk finds the same number
 * of quads either way; of two grids with that number, the remembered one
 * may be taken where the walk alone takes the one it meets first.
 */

/* Parameter of grid line i of n over [a, b] (warp F, NULL: uniform). */
static double grid_t(const double *F, double a, double b, uint32_t i, uint32_t n)
{
    if (F)
        return warp_t(F, a, b, (double)i / (double)n);
    return i == n ? b : a + (b - a) * (double)i / (double)n;
}

/* The cell's two boundary lines of direction dir (0: constant v, t = u)
 * that are not collapsed, as curves for tess_lines.c. */
typedef struct cell_lines {
    ts *T;
    const ts_cell *c;
    int dir, n;
    double k[2];
    const double *F; /* warp: the lines' t is the grid fraction */
    double a, b;     /* the range of t */
} cell_lines;

static void cell_line_point(void *user, int l, double t, double out[3])
{
    cell_lines *L = user;
    if (L->F) {
        const ts_cell *c = L->c;
        t = L->dir == 0 ? warp_t(L->F, c->u0, c->u1, t) : warp_t(L->F, c->v0, c->v1, t);
    }
    cell_point(L->T, L->c, L->dir == 0 ? t : L->k[l], L->dir == 0 ? L->k[l] : t, out);
}

static cell_lines lines_of(ts *T, const ts_cell *c, int dir)
{
    cell_lines L = {T, c, dir, 0, {0.0, 0.0}, cell_warp(T, c, dir), 0.0, 1.0};
    if (!L.F)
        L.a = dir == 0 ? c->u0 : c->v0, L.b = dir == 0 ? c->u1 : c->v1;
    for (int side = 0; side < 2; ++side) {
        const ts_edge *e = &T->edges[dir == 0 ? (side ? c->et : c->eb) : (side ? c->er : c->el)];
        if (!e->collapsed)
            L.k[L.n++] = dir == 0 ? (side ? c->v1 : c->v0) : (side ? c->u1 : c->u0);
    }
    return L;
}

/* Do the n-segment polylines along the cell's boundary lines of direction
 * dir pass tol (see geom__tess_lines_pass; *hint: where to look first)?
 * Collapsed lines pass. */
static int lines_pass(ts *T, const ts_cell *c, int dir, uint32_t n, double tol, double *hint)
{
    cell_lines L = lines_of(T, c, dir);
    return geom__tess_lines_pass(cell_line_point, &L, L.n, L.a, L.b, T->ksub, n, tol, hint);
}

/* Smallest segment count (at most cap) with which the boundary lines of
 * direction dir pass: every grid with fewer lines along dir fails. */
static uint32_t lines_bound(ts *T, const ts_cell *c, int dir, uint32_t cap, double tol)
{
    cell_lines L = lines_of(T, c, dir);
    return geom__tess_lines_bound(cell_line_point, &L, L.n, L.a, L.b, T->ksub, cap, tol);
}

/* Which collapsed cell edge grid corner (i, j) lies on (1 bottom, 2 top,
 * 3 left, 4 right), or 0: two corners on the same collapsed edge are one
 * vertex, and triangulate_cell drops the triangles between them. */
static int grid_pole(const ts *T, const ts_cell *c, uint32_t M, uint32_t N, uint32_t i,
                     uint32_t j)
{
    if (j == 0 && T->edges[c->eb].collapsed)
        return 1;
    if (j == N && T->edges[c->et].collapsed)
        return 2;
    if (i == 0 && T->edges[c->el].collapsed)
        return 3;
    if (i == M && T->edges[c->er].collapsed)
        return 4;
    return 0;
}

/* Quad (i, j) of the M x N grid of cell c, corners X (counter-clockwise
 * from (i, j)), split as local_quad splits it: do its triangles pass tol?
 * The worst sample of a failing quad goes to c->wu, c->wv. rect (NULL:
 * evaluate them): the quad's samples, its (K+1) x (K+1) lattice (both
 * triangles' lattices lie on it; rows of `stride` points, rect at the
 * quad's corner (i, j)). */
static int quad_passes(ts *T, ts_cell *c, uint32_t M, uint32_t N, uint32_t i, uint32_t j,
                       const double *const X[4], double tol, const double *rect, size_t stride)
{
    const uint32_t ii[4] = {i, i + 1, i + 1, i}, jj[4] = {j, j, j + 1, j + 1};
    double U[4], V[4];
    int pole[4];
    const double *Fu = cell_warp(T, c, 0), *Fv = cell_warp(T, c, 1);
    for (int k = 0; k < 4; ++k) {
        U[k] = grid_t(Fu, c->u0, c->u1, ii[k], M);
        V[k] = grid_t(Fv, c->v0, c->v1, jj[k], N);
        pole[k] = grid_pole(T, c, M, N, ii[k], jj[k]);
    }
    static const int split[2][6] = {{0, 1, 2, 0, 2, 3}, {0, 1, 3, 1, 2, 3}};
    double ac = dist3(X[0], X[2]), bd = dist3(X[1], X[3]);
    int first = split_ac(T, ac, bd) ? 0 : 1;
    /* pruning a uniform grid (T->prune > 0): its positions may differ from
     * these by T->prune, so where that can change the split, the quad fails
     * only if both splits fail */
    int nsplit = T->prune > 0.0 && fabs(ac - bd - 8.0 * T->weld_tol) <= 4.0 * T->prune ? 2 : 1;
    for (int sp = 0; sp < nsplit; ++sp) {
        const int *s = split[sp ? 1 - first : first];
        int ok = 1, live[2];
        for (int t = 0; t < 2; ++t) {
            const int *q = s + 3 * t;
            live[t] = !((pole[q[0]] && pole[q[0]] == pole[q[1]]) ||
                        (pole[q[1]] && pole[q[1]] == pole[q[2]]) ||
                        (pole[q[0]] && pole[q[0]] == pole[q[2]]));
        }
        for (int t = 0; t < 2 && ok; ++t) {
            const int *q = s + 3 * t, *o = s + 3 * (1 - t);
            if (!live[t])
                continue;
            const double *TX[3] = {X[q[0]], X[q[1]], X[q[2]]};
            const double *Y[3] = {X[o[0]], X[o[1]], X[o[2]]};
            const uint32_t L[3] = {(uint32_t)q[0], (uint32_t)q[1], (uint32_t)q[2]};
            const uint32_t M[3] = {(uint32_t)o[0], (uint32_t)o[1], (uint32_t)o[2]};
            int diag = shared_side(L, M);
            unsigned mask = diag >= 0 ? 1u << diag : 0u;
            double TU[3] = {U[q[0]], U[q[1]], U[q[2]]}, TV[3] = {V[q[0]], V[q[1]], V[q[2]]};
            double wu = 0.0, wv = 0.0;
            if (rect) {
                /* corner k of the quad at lattice (K cu[k], K cv[k]) */
                static const int cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
                int K = T->ksub;
                for (int a = 0; a <= K; ++a)
                    for (int b = 0; a + b <= K; ++b) {
                        int k = K - a - b;
                        size_t px = (size_t)(a * cu[q[0]] + b * cu[q[1]] + k * cu[q[2]]);
                        size_t py = (size_t)(a * cv[q[0]] + b * cv[q[1]] + k * cv[q[2]]);
                        memcpy(T->lat + LI(a, b), rect + 3 * (py * stride + px),
                               3 * sizeof(double));
                    }
            } else {
                tri_lattice(T, c, TX, TU, TV);
            }
            if (!(tri_error_lat(T, TX, TU, TV, Y, live[1 - t], mask, &wu, &wv) <= tol)) {
                c->wu = wu;
                c->wv = wv;
                ok = 0;
            }
        }
        if (ok)
            return 1;
    }
    return 0;
}

static void grid_point(ts *T, const ts_cell *c, uint32_t M, uint32_t N, uint32_t i, uint32_t j,
                       double *p)
{
    cell_point(T, c, grid_t(cell_warp(T, c, 0), c->u0, c->u1, i, M),
               grid_t(cell_warp(T, c, 1), c->v0, c->v1, j, N), p);
}

static uint32_t grid_index(const double *F, double a, double b, double t, uint32_t n)
{
    double f = (t - a) / (b - a);
    if (F)
        f = geom__tess_warp_f(F, WARP_N, f);
    f *= (double)n;
    if (!(f >= 0.0))
        return 0;
    return f >= (double)n ? n - 1 : (uint32_t)f;
}

/* Scratch rows of the grid search. */
typedef struct grid_rows {
    double *row;
    size_t cap;
    double *basis; /* a row's v basis values (K+1 sets), a column's u basis, work */
    size_t bcap;
    const double *spots; /* nspots (u, v): where other grids failed, tried early */
    int nspots;
} grid_rows;

/* Does quad (i, j) of the direct M x N grid of cell c pass tol? */
static int grid_quad_passes(ts *T, ts_cell *c, uint32_t M, uint32_t N, uint32_t i, uint32_t j,
                            double tol)
{
    double P[4][3];
    const uint32_t ii[4] = {i, i + 1, i + 1, i}, jj[4] = {j, j, j + 1, j + 1};
    for (int k = 0; k < 4; ++k)
        grid_point(T, c, M, N, ii[k], jj[k], P[k]);
    const double *X[4] = {P[0], P[1], P[2], P[3]};
    return quad_passes(T, c, M, N, i, j, X, tol, NULL, 0);
}

/* Does the direct M x N grid of cell c (inner: its quads off the cell's
 * boundary) pass tol? */
static geom_status grid_passes_in(ts *T, ts_cell *c, uint32_t M, uint32_t N, double tol,
                                  int inner, grid_rows *R, int *pass)
{
    *pass = 0;
    /* inner: only the quads not touching the cell's boundary (a stitched
     * cell has exactly these in common with the direct grid) */
    uint32_t ilo = inner ? 1 : 0, ihi = inner ? (M > 1 ? M - 1 : 0) : M;
    uint32_t jlo = inner ? 1 : 0, jhi = inner ? (N > 1 ? N - 1 : 0) : N;
    if (ilo >= ihi || jlo >= jhi) {
        *pass = 1;
        return GEOM_OK;
    }
    /* first the quad at the last worst point, then those at the places
     * where other grids failed, then the 3 x 3 quads around the first */
    const double *Fu = cell_warp(T, c, 0), *Fv = cell_warp(T, c, 1);
    uint32_t i0 = grid_index(Fu, c->u0, c->u1, c->wu, M);
    uint32_t j0 = grid_index(Fv, c->v0, c->v1, c->wv, N);
    uint32_t ic = i0 < ilo ? ilo : i0 >= ihi ? ihi - 1 : i0;
    uint32_t jc = j0 < jlo ? jlo : j0 >= jhi ? jhi - 1 : j0;
    if (!grid_quad_passes(T, c, M, N, ic, jc, tol))
        return GEOM_OK;
    for (int k = 0; k < R->nspots; ++k) {
        uint32_t i = grid_index(Fu, c->u0, c->u1, R->spots[2 * k], M);
        uint32_t j = grid_index(Fv, c->v0, c->v1, R->spots[2 * k + 1], N);
        i = i < ilo ? ilo : i >= ihi ? ihi - 1 : i;
        j = j < jlo ? jlo : j >= jhi ? jhi - 1 : j;
        if (!grid_quad_passes(T, c, M, N, i, j, tol))
            return GEOM_OK;
    }
    for (uint32_t i = i0 > ilo ? i0 - 1 : ilo; i <= i0 + 1 && i < ihi; ++i)
        for (uint32_t j = j0 > jlo ? j0 - 1 : jlo; j <= j0 + 1 && j < jhi; ++j)
            if ((i != ic || j != jc) && !grid_quad_passes(T, c, M, N, i, j, tol))
                return GEOM_OK;
    /* then all of them, a row of quads at a time, on the row's sample
     * lattice ((K+1) rows of samples, K per quad and row, at the same
     * parameters as the triangles' lattices): each sample evaluated once,
     * a quad's new columns just before it is checked, a row's first
     * samples taken from the row below it */
    int K = T->ksub;
    size_t W = (size_t)(ihi - ilo) * (size_t)K + 1;
    size_t need = 3 * W * ((size_t)K + 1);
    if (need > ((size_t)1 << 22)) { /* over 32 MB (many quads and samples): quad by quad */
        for (uint32_t j = jlo; j < jhi; ++j)
            for (uint32_t i = ilo; i < ihi; ++i)
                if (!grid_quad_passes(T, c, M, N, i, j, tol))
                    return GEOM_OK;
        *pass = 1;
        return GEOM_OK;
    }
    if (need > R->cap) {
        if (R->row)
            ts_free(T, R->row, R->cap, sizeof(double));
        R->cap = need + need / 2;
        R->row = ts_alloc(T, R->cap, sizeof(double));
        if (!R->row) {
            R->cap = 0;
            return GEOM_ERR_NOMEM;
        }
    }
    double *lat = R->row;
    /* the samples' basis values: v per row (K+1 sets), u per column, each
     * computed once (geom__surface_span_point's point, bitwise) */
    const geom_nurbs_surface *sf = T->surf[c->surf].s;
    int pu = sf->degree_u, pv = sf->degree_v;
    int direct = c->ku != LOCATE;
    size_t bneed = ((size_t)K + 1) * ((size_t)pv + 1) + (size_t)pu + 1 +
                   geom__bs_basis_work(pu > pv ? pu : pv);
    if (direct && bneed > R->bcap) {
        if (R->basis)
            ts_free(T, R->basis, R->bcap, sizeof(double));
        R->bcap = bneed;
        R->basis = ts_alloc(T, R->bcap, sizeof(double));
        if (!R->basis) {
            R->bcap = 0;
            return GEOM_ERR_NOMEM;
        }
    }
    double *Nv = R->basis, *Nu = direct ? Nv + ((size_t)K + 1) * ((size_t)pv + 1) : NULL;
    double *bw = direct ? Nu + pu + 1 : NULL;
    /* rows from just below the worst point up, then the rest: a grid that
     * fails usually fails near where the last one did */
    uint32_t nr = jhi - jlo, js = j0 > jlo + 2 ? j0 - 2 : jlo;
    if (js >= jhi)
        js = jlo;
    uint32_t prev = UINT32_MAX; /* the row whose samples are all in lat */
    for (uint32_t r = 0; r < nr; ++r) {
        uint32_t j = js + r < jhi ? js + r : js + r - nr;
        double va = grid_t(Fv, c->v0, c->v1, j, N), vb = grid_t(Fv, c->v0, c->v1, j + 1, N);
        if (direct)
            for (int q = 0; q <= K; ++q) {
                double v = q == 0 ? va : q == K ? vb : va + (vb - va) * (double)q / (double)K;
                geom__bs_basis(pv, sf->knots_v, c->kv, v, Nv + (size_t)q * ((size_t)pv + 1), bw);
            }
        int q0 = 0;
        if (prev != UINT32_MAX && j == prev + 1) {
            memcpy(lat, lat + 3 * W * (size_t)K, 3 * W * sizeof(double));
            q0 = 1;
        }
        prev = UINT32_MAX;
        for (uint32_t i = ilo; i < ihi; ++i) {
            double ua = grid_t(Fu, c->u0, c->u1, i, M), ub = grid_t(Fu, c->u0, c->u1, i + 1, M);
            size_t x0 = (size_t)(i - ilo) * (size_t)K;
            for (int p = i == ilo ? 0 : 1; p <= K; ++p) {
                double u = p == 0 ? ua : p == K ? ub : ua + (ub - ua) * (double)p / (double)K;
                if (direct) {
                    geom__bs_basis(pu, sf->knots_u, c->ku, u, Nu, bw);
                    for (int q = q0; q <= K; ++q)
                        geom__surface_span_combine(sf, c->ku, c->kv, Nu,
                                                   Nv + (size_t)q * ((size_t)pv + 1),
                                                   lat + 3 * ((size_t)q * W + x0 + (size_t)p));
                    T->evals += (size_t)(K + 1 - q0);
                    continue;
                }
                for (int q = q0; q <= K; ++q) {
                    double v = q == 0 ? va : q == K ? vb : va + (vb - va) * (double)q / (double)K;
                    cell_point(T, c, u, v, lat + 3 * ((size_t)q * W + x0 + (size_t)p));
                }
            }
            const double *base = lat + 3 * x0;
            size_t top = 3 * W * (size_t)K, k3 = 3 * (size_t)K;
            const double *X[4] = {base, base + k3, base + top + k3, base + top};
            if (!quad_passes(T, c, M, N, i, j, X, tol, base, W))
                return GEOM_OK;
        }
        prev = j;
    }
    *pass = 1;
    return GEOM_OK;
}

/* Does the direct M x N grid of cell c pass tol? */
static geom_status grid_passes(ts *T, ts_cell *c, uint32_t M, uint32_t N, double tol,
                               grid_rows *R, int *pass)
{
    return grid_passes_in(T, c, M, N, tol, 0, R, pass);
}

/* M x *phi passes: lower *phi to the smallest N that passes by bisection
 * (nlb - 1 fails along the boundary lines; one_less: try *phi - 1 first).
 * N - 1 has failed (or is nlb - 1) on return. */
static geom_status grid_lower(ts *T, ts_cell *c, uint32_t M, uint32_t nlb, int one_less,
                              double tol, grid_rows *R, uint32_t *phi)
{
    uint32_t lo = nlb - 1, hi = *phi;
    for (int step = 0; hi - lo > 1; ++step) {
        uint32_t mid = one_less && step == 0 ? hi - 1 : lo + (hi - lo) / 2;
        int pass;
        geom_status st = grid_passes(T, c, M, mid, tol, R, &pass);
        if (st != GEOM_OK)
            return st;
        if (pass)
            hi = mid;
        else
            lo = mid;
    }
    *phi = hi;
    return GEOM_OK;
}

/* The staircase walk under tol: *pm x *pn (taken to pass) is replaced by
 * the passing grid with the fewest quads. M is visited from mfirst
 * outward, so a good guess finds the best product early and the other
 * columns mostly fail at their first quads. */
static geom_status grid_search(ts *T, ts_cell *c, double tol, uint32_t mfirst, uint32_t *pm,
                               uint32_t *pn, grid_rows *R)
{
    uint64_t best = (uint64_t)*pm * *pn;
    uint32_t mlb = lines_bound(T, c, 0, *pm, tol), nlb = lines_bound(T, c, 1, *pn, tol);
    /* aspect ratios within 4x of the first guess: bounds the walk where the
     * boundary lines bound nothing (straight lines give 1) */
    uint64_t mlo = mfirst / 4 > mlb ? mfirst / 4 : mlb, mhi = 4 * (uint64_t)mfirst;
    if (mfirst < mlo)
        mfirst = (uint32_t)mlo;
    /* a cell whose walk starts as a remembered one's did tries that answer
     * first: when it passes, the walk's other columns then mostly fail at
     * their first quads instead of each passing in turn with a slightly
     * smaller product (every passing check evaluates the whole grid) */
    const struct ts_grid_memo *g = NULL;
    for (unsigned k = 0; k < GRID_MEMO; ++k) {
        const struct ts_grid_memo *e = &T->grid_memo[k];
        if (e->m && e->tol == tol && e->mfirst == mfirst && e->mlb == mlb && e->nlb == nlb)
            g = e;
    }
    uint32_t mskip = 0;
    if (g && (uint64_t)g->m * g->n < best && g->m >= mlo && g->m <= mhi && g->n >= nlb) {
        int pass;
        geom_status st = grid_passes(T, c, g->m, g->n, tol, R, &pass);
        if (st != GEOM_OK)
            return st;
        if (pass) {
            /* the same cell's answer again: one less usually fails */
            uint32_t hi = g->n;
            st = grid_lower(T, c, g->m, nlb, 1, tol, R, &hi);
            if (st != GEOM_OK)
                return st;
            best = (uint64_t)g->m * hi;
            *pm = g->m;
            *pn = hi;
            mskip = g->m; /* hi - 1 failed (or is under the bound) */
        }
    }
    for (uint64_t k = 0;; ++k) {
        int any = 0;
        for (int side = 0; side < 2; ++side) {
            uint64_t M;
            if (side == 0) {
                M = mfirst + k;
                if (M * nlb >= best || M > MAX_GRID || M > mhi)
                    continue;
            } else {
                if (k == 0 || mfirst < mlo + k)
                    continue;
                M = mfirst - k;
            }
            any = 1;
            if (M == mskip)
                continue;
            uint64_t n = (best - 1) / M;
            if (n < nlb || n > MAX_GRID)
                continue;
            int pass;
            geom_status st = grid_passes(T, c, (uint32_t)M, (uint32_t)n, tol, R, &pass);
            if (st != GEOM_OK)
                return st;
            if (!pass)
                continue;
            uint32_t hi = (uint32_t)n;
            st = grid_lower(T, c, (uint32_t)M, nlb, 0, tol, R, &hi);
            if (st != GEOM_OK)
                return st;
            best = M * hi;
            *pm = (uint32_t)M;
            *pn = hi;
        }
        if (!any)
            break;
    }
    struct ts_grid_memo *e = &T->grid_memo[T->grid_memo_next++ % GRID_MEMO];
    e->tol = tol, e->mfirst = mfirst, e->mlb = mlb, e->nlb = nlb, e->m = *pm, e->n = *pn;
    return GEOM_OK;
}

/* The passing grid with the fewest quads for cell c (see above); c->M, c->N
 * pass on entry and are kept unless a smaller one passes. The best aspect
 * ratio is found first at a 4x to 8x coarser grid (tolerance times the
 * square of the scale: the chordal error goes as the step squared), where
 * each check costs a sixteenth or less. */
static geom_status optimise_cell(ts *T, ts_cell *c)
{
    grid_rows R = {NULL, 0, NULL, 0, NULL, 0};
    uint32_t M = c->M, N = c->N, mfirst = M;
    uint32_t sc = (M < N ? M : N) / 12;
    geom_status st = GEOM_OK;
    if (sc >= 2) {
        uint32_t cm = (M + sc - 1) / sc, cn = (N + sc - 1) / sc;
        double wu = c->wu, wv = c->wv;
        st = grid_search(T, c, T->tol * (double)sc * (double)sc, cm, &cm, &cn, &R);
        c->wu = wu;
        c->wv = wv;
        mfirst = cm * sc;
    }
    if (st == GEOM_OK)
        st = grid_search(T, c, T->tol, mfirst, &M, &N, &R);
    if (R.row)
        ts_free(T, R.row, R.cap, sizeof(double));
    if (R.basis)
        ts_free(T, R.basis, R.bcap, sizeof(double));
    c->M = M;
    c->N = N;
    return st;
}

static int sig_changed(const ts_cell *c, const uint32_t *old)
{
    for (int k = 0; k < 6; ++k)
        if (c->sig[k] != old[k])
            return 1;
    return 0;
}

/* Triangulate c again, and check it again when its signature changed (or
 * it was never checked). */
static geom_status retriangulate(ts *T, ts_cell *c)
{
    uint32_t old[6];
    memcpy(old, c->sig, sizeof old);
    geom_status st = triangulate_cell(T, c);
    if (st == GEOM_OK && (!c->checked || sig_changed(c, old)))
        check_cell(T, c);
    return st;
}

/* ------------------------------------------------- the uniform alternative */

/*
 * Never more triangles than a uniform grid, by construction. The uniform
 * family: every knot-span cell of every surface gets the same gu x gv grid
 * (what uniform mode makes with grid_u = gu, grid_v = gv, per_surface 0,
 * the same check_subdivisions). After the adaptive result (A triangles,
 * every cell within tol) is known, every (gu, gv) whose triangle count can
 * be below A is either shown to fail or tessellated as uniform mode would
 * and checked; the fewest-triangle one that passes with fewer than A
 * triangles is taken instead of the adaptive result.
 *
 * Counts: a cell's gu x gv grid has at least 2 gu gv triangles, minus gu
 * (gv) for each collapsed side along u (v): the direct grid drops at most
 * one triangle per quad along a collapsed side, a stitched one (edges with
 * more samples) has 2 gu gv - 2 gu - 2 gv + the sides' samples. So pairs
 * with 2 n gu gv - gu CU - gv CV >= A are skipped.
 *
 * Showing a pair fails uses only checks of triangles that uniform mode
 * makes: (1) lines: a cell whose edges all carry its own grid in uniform
 * mode (no edge is welded to an edge running the other way, or gu == gv)
 * is triangulated as the direct grid, so the chords along its two boundary
 * lines of each direction are triangle sides with the same side samples:
 * if they fail at gu (or gv), every pair with that gu (gv) fails; (2) the
 * grid: the direct grid's triangles of such a cell, or, for a cell that is
 * stitched, its interior quads (those not touching the boundary, which the
 * stitched triangulation has too). Positions here are evaluated on the
 * cell, which can differ from uniform mode's welded edge samples by the
 * weld tolerance and rounding, so a pair is dropped only when a check
 * fails by more than T->prune = that margin, and a quad whose diagonals
 * are nearly equal fails only if both splits do. The pairs left are run
 * as uniform mode runs them (vertices, triangulation, check: the same
 * code), in increasing gu, each gu's gv upward until one passes.
 */

#define NSPOT 8

/* Saved adaptive grid of every cell. */
typedef struct uni_state {
    uint32_t *mn;    /* 2 per cell */
    uint8_t *stitch; /* per cell: an edge welded to one running the other way */
    double *hint;    /* 2 per cell: lines' last failing parameter */
    double *spots;    /* per cell NSPOT (u, v): where its grids failed */
    uint32_t *nspot;  /* per cell: spots written (a ring of NSPOT) */
    uint8_t *feas[2]; /* per count: 0 unknown, 1 lines pass, 2 fail */
    size_t fcap[2];
    uint32_t lastfail[2]; /* the cell whose lines failed last, per direction */
    uint32_t lastgrid;    /* the cell whose grid failed last */
} uni_state;

/* Do the boundary lines of direction dir of every unstitched cell pass at
 * count g (tolerance T->tol + T->prune)? Memoised per g. */
static geom_status uni_lines(ts *T, uni_state *U, int dir, uint32_t g, int *ok)
{
    if (g >= U->fcap[dir]) {
        size_t cap = U->fcap[dir];
        geom_status st = geom__grow(T->alloc, (void **)&U->feas[dir], &cap, (size_t)g + 1, 1);
        if (st != GEOM_OK)
            return st;
        memset(U->feas[dir] + U->fcap[dir], 0, cap - U->fcap[dir]);
        U->fcap[dir] = cap;
    }
    if (!U->feas[dir][g]) {
        int pass = 1;
        double ptol = T->tol + T->prune;
        for (size_t r = 0; r < T->ncells && pass; ++r) {
            uint32_t i = (uint32_t)((U->lastfail[dir] + r) % T->ncells);
            if (U->stitch[i])
                continue;
            if (!lines_pass(T, &T->cells[i], dir, g, ptol, &U->hint[2 * (size_t)i + (size_t)dir])) {
                pass = 0;
                U->lastfail[dir] = i;
            }
        }
        U->feas[dir][g] = pass ? 1 : 2;
    }
    *ok = U->feas[dir][g] == 1;
    return GEOM_OK;
}

/* Can uniform gu x gv pass (no cell's grid fails by more than the
 * margin)? */
static geom_status uni_grids(ts *T, uni_state *U, uint32_t gu, uint32_t gv, grid_rows *R, int *ok)
{
    *ok = 1;
    double ptol = T->tol + T->prune;
    for (size_t r = 0; r < T->ncells && *ok; ++r) {
        uint32_t i = (uint32_t)((U->lastgrid + r) % T->ncells);
        ts_cell *c = &T->cells[i];
        double wu = c->wu, wv = c->wv;
        int pass;
        double *sp = U->spots + 2 * NSPOT * (size_t)i;
        R->spots = sp;
        R->nspots = U->nspot[i] < NSPOT ? (int)U->nspot[i] : NSPOT;
        geom_status st = grid_passes_in(T, c, gu, gv, ptol, U->stitch[i] && gu != gv, R, &pass);
        R->nspots = 0;
        if (st != GEOM_OK)
            return st;
        if (!pass) {
            *ok = 0;
            U->lastgrid = i;
            /* remember where, unless a remembered place is that close */
            int near = 0, held = U->nspot[i] < NSPOT ? (int)U->nspot[i] : NSPOT;
            for (int k = 0; k < held; ++k)
                near |= fabs(sp[2 * k] - c->wu) <= 0.02 * (c->u1 - c->u0) &&
                        fabs(sp[2 * k + 1] - c->wv) <= 0.02 * (c->v1 - c->v0);
            if (!near) {
                size_t k = U->nspot[i] % NSPOT;
                sp[2 * k] = c->wu, sp[2 * k + 1] = c->wv;
                U->nspot[i] = U->nspot[i] % NSPOT + NSPOT * (U->nspot[i] >= NSPOT) + 1;
            }
        } else {
            c->wu = wu;
            c->wv = wv;
        }
    }
    return GEOM_OK;
}

/* Uniform mode's pass for gu x gv: every cell triangulated and checked;
 * *ok when all pass with fewer than `below` triangles (*count). */
static geom_status uni_run(ts *T, uint32_t gu, uint32_t gv, size_t below, int *ok, size_t *count)
{
    *ok = 0;
    for (size_t i = 0; i < T->ncells; ++i)
        T->cells[i].M = gu, T->cells[i].N = gv;
    geom_status st = assign_vertices(T);
    size_t n = 0;
    for (size_t i = 0; i < T->ncells && st == GEOM_OK; ++i) {
        ts_cell *c = &T->cells[i];
        st = retriangulate(T, c);
        n += T->nltri;
        if (st != GEOM_OK || !(c->err <= T->tol) || n >= below)
            return st;
    }
    *ok = st == GEOM_OK;
    *count = n;
    return st;
}

static void uni_free(ts *T, uni_state *U)
{
    if (U->mn)
        ts_free(T, U->mn, 2 * T->ncells, sizeof(uint32_t));
    if (U->stitch)
        ts_free(T, U->stitch, T->ncells, 1);
    if (U->hint)
        ts_free(T, U->hint, 2 * T->ncells, sizeof(double));
    if (U->spots)
        ts_free(T, U->spots, 2 * NSPOT * T->ncells, sizeof(double));
    if (U->nspot)
        ts_free(T, U->nspot, T->ncells, sizeof(uint32_t));
    for (int d = 0; d < 2; ++d)
        if (U->feas[d])
            ts_free(T, U->feas[d], U->fcap[d], 1);
}

/* The search (see above); A: the adaptive result's triangles. On return
 * every cell has the grid to output: the best uniform one if it has fewer
 * than A triangles, the adaptive one otherwise; *chosen = 1 in the first
 * case (its gu x gv in *pgu, *pgv). */
static geom_status uniform_search(ts *T, size_t A, int *chosen, uint32_t *pgu, uint32_t *pgv)
{
    *chosen = 0;
    size_t nc = T->ncells;
    int warp = T->warp_on;
    uni_state U;
    memset(&U, 0, sizeof U);
    U.mn = ts_alloc(T, 2 * nc, sizeof(uint32_t));
    U.stitch = ts_alloc(T, nc, 1);
    U.hint = ts_alloc(T, 2 * nc, sizeof(double));
    U.spots = ts_alloc(T, 2 * NSPOT * nc, sizeof(double));
    U.nspot = ts_alloc(T, nc, sizeof(uint32_t));
    grid_rows R = {NULL, 0, NULL, 0, NULL, 0};
    geom_status st = GEOM_OK;
    size_t best = A;
    uint32_t bu = 0, bv = 0;
    double CU = 0.0, CV = 0.0;
    if (!U.mn || !U.stitch || !U.hint || !U.spots || !U.nspot) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    for (size_t i = 0; i < nc; ++i) {
        const ts_cell *c = &T->cells[i];
        U.mn[2 * i] = c->M, U.mn[2 * i + 1] = c->N;
        U.hint[2 * i] = U.hint[2 * i + 1] = NAN;
        U.nspot[i] = 0;
        const uint32_t es[4] = {c->eb, c->et, c->el, c->er};
        U.stitch[i] = 0;
        for (int k = 0; k < 4; ++k) {
            const ts_edge *e = &T->edges[es[k]];
            if (e->collapsed)
                *(k < 2 ? &CU : &CV) += 1.0;
            if (e->partner != NONE32 && T->edges[e->partner].dir != e->dir)
                U.stitch[i] = 1;
        }
    }
    T->warp_on = 0; /* uniform grids: uniform lines */
    double a2 = 2.0 * (double)nc;
#define LB(gu, gv) (a2 * (double)(gu) * (double)(gv) - (double)(gu) * CU - (double)(gv) * CV)
    /* a count that does not grow with gu or gv bounds nothing */
    if (!(a2 > CU && a2 > CV))
        goto done;
    T->prune = T->weld_tol > 0.0 ? T->weld_tol : DBL_MIN;
    /* smallest counts whose lines pass */
    uint32_t g0[2] = {0, 0};
    for (int d = 0; d < 2; ++d) {
        for (uint32_t g = 1; g <= MAX_GRID && LB(d ? 1 : g, d ? g : 1) < (double)best; ++g) {
            int ok;
            st = uni_lines(T, &U, d, g, &ok);
            if (st != GEOM_OK)
                goto done;
            if (ok) {
                g0[d] = g;
                break;
            }
        }
        if (!g0[d])
            goto done; /* no count along d passes under A triangles */
    }
    /* beyond the smallest counts the lines are checked only up to twice
     * them (a passing count costs a walk along every line, and the grids'
     * own check covers the lines' chords as well) */
    for (uint32_t gu = g0[0]; gu <= MAX_GRID && LB(gu, g0[1]) < (double)best; ++gu) {
        int ok = 1;
        if (gu <= 2 * g0[0])
            st = uni_lines(T, &U, 0, gu, &ok);
        if (st != GEOM_OK)
            goto done;
        if (!ok)
            continue;
        for (uint32_t gv = g0[1]; gv <= MAX_GRID && LB(gu, gv) < (double)best; ++gv) {
            ok = 1;
            if (gv <= 2 * g0[1])
                st = uni_lines(T, &U, 1, gv, &ok);
            if (st == GEOM_OK && ok)
                st = uni_grids(T, &U, gu, gv, &R, &ok);
            if (st != GEOM_OK)
                goto done;
            if (!ok)
                continue;
            size_t count = 0;
            T->prune = 0.0;
            st = uni_run(T, gu, gv, best, &ok, &count);
            T->prune = T->weld_tol > 0.0 ? T->weld_tol : DBL_MIN;
            if (st != GEOM_OK)
                goto done;
            if (ok) {
                best = count;
                bu = gu, bv = gv;
                break; /* a larger gv has more triangles */
            }
        }
    }
#undef LB
    if (bu) {
        *chosen = 1;
        *pgu = bu, *pgv = bv;
    }
done:
    T->prune = 0.0;
    T->warp_on = warp && !*chosen;
    if (U.mn)
        for (size_t i = 0; i < nc; ++i) {
            T->cells[i].M = *chosen ? *pgu : U.mn[2 * i];
            T->cells[i].N = *chosen ? *pgv : U.mn[2 * i + 1];
        }
    if (R.row)
        ts_free(T, R.row, R.cap, sizeof(double));
    if (R.basis)
        ts_free(T, R.basis, R.bcap, sizeof(double));
    uni_free(T, &U);
    return st;
}

/* ---------------------------------------------------------------- output */

static geom_status emit_cell(ts *T, ts_cell *c, unsigned attrs, int uv_norm)
{
    const ts_surf *ss = &T->surf[c->surf];
    int flip = ss->flip;
    uint32_t *cn = NULL, *cuv = NULL, *ct = NULL;
    size_t nl = T->nloc;
    geom_status st = GEOM_OK;
    if (attrs) {
        cn = ts_alloc(T, 3 * nl, sizeof(uint32_t));
        if (!cn)
            return GEOM_ERR_NOMEM;
        cuv = cn + nl;
        ct = cn + 2 * nl;
        for (size_t k = 0; k < nl && st == GEOM_OK; ++k) {
            double u = T->lu[k], v = T->lv[k];
            cn[k] = cuv[k] = ct[k] = NONE32;
            if (attrs & (GEOM_SURFACE_ATTR_NORMAL | GEOM_SURFACE_ATTR_TANGENT)) {
                double n[3], t[3];
                T->counting = 1;
                cell_normal(T, c, u, v, n, t);
                T->counting = 0;
                if (flip)
                    n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
                if (attrs & GEOM_SURFACE_ATTR_NORMAL)
                    st = pool_add(T, &T->pn, n, &cn[k]);
                if (st == GEOM_OK && (attrs & GEOM_SURFACE_ATTR_TANGENT)) {
                    double t4[4] = {t[0], t[1], t[2], flip ? -1.0 : 1.0};
                    st = pool_add(T, &T->pt, t4, &ct[k]);
                }
            }
            if (st == GEOM_OK && (attrs & GEOM_SURFACE_ATTR_UV)) {
                double uv[2] = {u, v};
                if (uv_norm) {
                    uv[0] = (u - ss->dom[0]) / (ss->dom[1] - ss->dom[0]);
                    uv[1] = (v - ss->dom[2]) / (ss->dom[3] - ss->dom[2]);
                }
                st = pool_add(T, &T->puv, uv, &cuv[k]);
            }
        }
    }
    for (size_t t = 0; t < T->nltri && st == GEOM_OK; ++t) {
        uint32_t L[3] = {T->ltri[3 * t], T->ltri[3 * t + 1], T->ltri[3 * t + 2]};
        if (flip) {
            uint32_t x = L[1];
            L[1] = L[2];
            L[2] = x;
        }
        if (T->ntri >= T->max_tri) {
            st = GEOM_ERR_LIMIT;
            break;
        }
        st = geom__grow(T->alloc, (void **)&T->tri, &T->cap_tri, 3 * (T->ntri + 1), sizeof(uint32_t));
        if (st == GEOM_OK && attrs)
            st = geom__grow(T->alloc, (void **)&T->tcorn, &T->cap_tcorn, 9 * (T->ntri + 1),
                         sizeof(uint32_t));
        if (st == GEOM_OK)
            st = geom__grow(T->alloc, (void **)&T->tsurf, &T->cap_tsurf, T->ntri + 1, sizeof(uint32_t));
        if (st != GEOM_OK)
            break;
        T->tsurf[T->ntri] = T->surf[c->surf].orig;
        for (int k = 0; k < 3; ++k)
            T->tri[3 * T->ntri + (size_t)k] = T->lvert[L[k]];
        if (attrs)
            for (int k = 0; k < 3; ++k) {
                T->tcorn[9 * T->ntri + (size_t)k] = cn[L[k]];
                T->tcorn[9 * T->ntri + 3 + (size_t)k] = cuv[L[k]];
                T->tcorn[9 * T->ntri + 6 + (size_t)k] = ct[L[k]];
            }
        T->ntri++;
    }
    if (cn)
        ts_free(T, cn, 3 * nl, sizeof(uint32_t));
    return st;
}

/* ------------------------------------------------------------------ main */

static void ts_release(ts *T)
{
    for (size_t k = 0; k < T->nsurf && T->surf; ++k) {
        ts_surf *s = &T->surf[k];
        if (s->ub)
            ts_free(T, s->ub, s->nbu + 1, sizeof(double));
        if (s->vb)
            ts_free(T, s->vb, s->nbv + 1, sizeof(double));
        if (s->ku)
            ts_free(T, s->ku, s->nbu, sizeof(size_t));
        if (s->kv)
            ts_free(T, s->kv, s->nbv, sizeof(size_t));
        for (int d = 0; d < 2; ++d) {
            size_t nb = d ? s->nbv : s->nbu;
            if (s->wF[d])
                ts_free(T, s->wF[d], nb * (WARP_N + 1), sizeof(double));
            if (s->won[d])
                ts_free(T, s->won[d], nb, 1);
        }
    }
    if (T->surf)
        ts_free(T, T->surf, T->nsurf, sizeof(ts_surf));
    if (T->cells)
        ts_free(T, T->cells, T->ncells, sizeof(ts_cell));
    if (T->nodes)
        ts_free(T, T->nodes, T->nnodes, sizeof(ts_node));
    if (T->parent)
        ts_free(T, T->parent, T->nnodes, sizeof(uint32_t));
    if (T->edges)
        ts_free(T, T->edges, T->nedges, sizeof(ts_edge));
    if (T->pos)
        ts_free(T, T->pos, T->cap_verts, sizeof(double));
    if (T->lu)
        ts_free(T, T->lu, T->cap_lu, sizeof(double));
    if (T->lv)
        ts_free(T, T->lv, T->cap_lv, sizeof(double));
    if (T->lvert)
        ts_free(T, T->lvert, T->cap_lvert, sizeof(uint32_t));
    if (T->lnorm)
        ts_free(T, T->lnorm, 6 * T->cap_lnorm, sizeof(double));
    if (T->ltri)
        ts_free(T, T->ltri, T->cap_ltri, sizeof(uint32_t));
    if (T->lmate)
        ts_free(T, T->lmate, T->cap_lmate, sizeof(uint32_t));
    if (T->ldiag)
        ts_free(T, T->ldiag, T->cap_ldiag, 1);
    if (T->tri)
        ts_free(T, T->tri, T->cap_tri, sizeof(uint32_t));
    if (T->tcorn)
        ts_free(T, T->tcorn, T->cap_tcorn, sizeof(uint32_t));
    if (T->tsurf)
        ts_free(T, T->tsurf, T->cap_tsurf, sizeof(uint32_t));
    pool_free(T, &T->pn);
    pool_free(T, &T->puv);
    pool_free(T, &T->pt);
    if (T->lat)
        ts_free(T, T->lat, 3 * (size_t)(T->ksub + 1) * (size_t)(T->ksub + 2) / 2, sizeof(double));
    if (T->memo)
        ts_free(T, T->memo, MEMO_SIZE, sizeof(ts_memo));
    geom__scratch_free(&T->sc);
}

/* Weld the corner normals of each vertex that agree within the angle tol
 * (radians): corners of one vertex whose normals differ only by the
 * rounding of two patches' evaluations (a G1 seam) take the first such
 * normal, so a renderer's vertex is not split for a last-bit difference.
 * Corners whose normals differ by more (creases, poles seen from different
 * patches) keep their own. cn: 3*ntri corner normal indices, tri: compact
 * vertex ids (nv of them). Returns the corners changed, or SIZE_MAX on no
 * memory. */
static size_t weld_normals(ts *T, uint32_t *cn, size_t nv, double tol)
{
    size_t nc = 3 * T->ntri, changed = 0;
    size_t *start = ts_alloc(T, nv + 1, sizeof(size_t));
    uint32_t *order = ts_alloc(T, nc ? nc : 1, sizeof(uint32_t));
    if (!start || !order) {
        if (start)
            ts_free(T, start, nv + 1, sizeof(size_t));
        if (order)
            ts_free(T, order, nc ? nc : 1, sizeof(uint32_t));
        return SIZE_MAX;
    }
    /* corners grouped by vertex (counting sort) */
    memset(start, 0, (nv + 1) * sizeof(size_t));
    for (size_t k = 0; k < nc; ++k)
        start[T->tri[k] + 1]++;
    for (size_t v = 0; v < nv; ++v)
        start[v + 1] += start[v];
    for (size_t k = 0; k < nc; ++k)
        order[start[T->tri[k]]++] = (uint32_t)k;
    for (size_t v = nv; v > 0; --v)
        start[v] = start[v - 1];
    start[0] = 0;
    double cmin = cos(tol);
    const double *N = T->pn.vals;
    for (size_t v = 0; v < nv; ++v) {
        /* the distinct normals of this vertex are few: quadratic is fine */
        for (size_t i = start[v]; i < start[v + 1]; ++i) {
            uint32_t a = cn[order[i]];
            if (a == NONE32)
                continue;
            for (size_t j = start[v]; j < i; ++j) {
                uint32_t b = cn[order[j]];
                if (b == a || b == NONE32)
                    break;
                const double *na = N + 3 * (size_t)a, *nb = N + 3 * (size_t)b;
                double d = na[0] * nb[0] + na[1] * nb[1] + na[2] * nb[2];
                double la = na[0] * na[0] + na[1] * na[1] + na[2] * na[2];
                double lb = nb[0] * nb[0] + nb[1] * nb[1] + nb[2] * nb[2];
                if (la > 0.0 && lb > 0.0 && d >= cmin * sqrt(la * lb)) {
                    cn[order[i]] = b;
                    changed++;
                    break;
                }
            }
        }
    }
    ts_free(T, start, nv + 1, sizeof(size_t));
    ts_free(T, order, nc ? nc : 1, sizeof(uint32_t));
    return changed;
}

/* Build the mesh from the emitted triangles: compact vertices, then one
 * build with the face and corner channels. */
static geom_status build_mesh(ts *T, geom_mesh *out, unsigned attrs, geom_diag *diag)
{
    uint32_t *map = ts_alloc(T, T->nverts, sizeof(uint32_t));
    if (!map)
        return GEOM_ERR_NOMEM;
    for (size_t i = 0; i < T->nverts; ++i)
        map[i] = NONE32;
    size_t nv = 0;
    for (size_t t = 0; t < 3 * T->ntri; ++t) {
        uint32_t v = T->tri[t];
        if (map[v] == NONE32) {
            /* compact positions in place: new index nv <= v */
            map[v] = (uint32_t)nv;
            nv++;
        }
        T->tri[t] = map[v];
    }
    double *xyz = ts_alloc(T, 3 * nv, sizeof(double));
    uint32_t *sizes = ts_alloc(T, T->ntri, sizeof(uint32_t));
    uint32_t *cidx[3] = {NULL, NULL, NULL};
    double *surf = NULL;
    geom_status st = GEOM_OK;
    if (!xyz || !sizes) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    for (size_t i = 0; i < T->nverts; ++i)
        if (map[i] != NONE32)
            memcpy(xyz + 3 * (size_t)map[i], T->pos + 3 * i, 3 * sizeof(double));
    for (size_t t = 0; t < T->ntri; ++t)
        sizes[t] = 3;
    /* the streams: the source surface per face, then the corner channels */
    static const char *const names[3] = {"normal", "uv", "tangent"};
    static const size_t ncomp[3] = {3, 2, 4};
    const unsigned bits[3] = {GEOM_SURFACE_ATTR_NORMAL, GEOM_SURFACE_ATTR_UV,
                              GEOM_SURFACE_ATTR_TANGENT};
    ts_pool *pools[3] = {&T->pn, &T->puv, &T->pt};
    geom_mesh_build_channel chans[4];
    size_t nch = 0;
    memset(chans, 0, sizeof chans);
    if (T->opt->attributes & GEOM_SURFACE_ATTR_SOURCE) {
        surf = ts_alloc(T, T->ntri, sizeof(double));
        if (!surf) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        for (size_t t = 0; t < T->ntri; ++t)
            surf[t] = (double)T->tsurf[t];
        chans[nch].name = "surface";
        chans[nch].domain = GEOM_MESH_DOMAIN_FACE;
        chans[nch].ncomp = 1;
        chans[nch].values = surf;
        nch++;
    }
    for (int ch = 0; ch < 3; ++ch) {
        if (!(attrs & bits[ch]))
            continue;
        cidx[ch] = ts_alloc(T, 3 * T->ntri, sizeof(uint32_t));
        if (!cidx[ch]) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        for (size_t t = 0; t < T->ntri; ++t)
            for (size_t k = 0; k < 3; ++k)
                cidx[ch][3 * t + k] = T->tcorn[9 * t + 3 * (size_t)ch + k];
        if (ch == 0 && T->normal_weld > 0.0) {
            size_t w = weld_normals(T, cidx[0], nv, T->normal_weld);
            if (w == SIZE_MAX) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
            T->welded_normals = w;
        }
        chans[nch].name = names[ch];
        chans[nch].domain = GEOM_MESH_DOMAIN_CORNER;
        chans[nch].ncomp = ncomp[ch];
        chans[nch].n_values = pools[ch]->n;
        chans[nch].values = pools[ch]->vals;
        chans[nch].indices = cidx[ch];
        nch++;
    }
    geom_mesh_clear(out);
    geom_mesh_build_options bo;
    memset(&bo, 0, sizeof bo);
    bo.keep_orientation = T->opt->keep_orientation || T->opt->no_weld;
    bo.channels = chans;
    bo.n_channels = nch;
    st = geom_mesh_build(out, nv, xyz, T->ntri, sizes, T->tri, &bo, NULL, diag);
done:
    for (int ch = 0; ch < 3; ++ch)
        if (cidx[ch])
            ts_free(T, cidx[ch], 3 * T->ntri, sizeof(uint32_t));
    if (surf)
        ts_free(T, surf, T->ntri, sizeof(double));
    ts_free(T, map, T->nverts, sizeof(uint32_t));
    if (xyz)
        ts_free(T, xyz, 3 * nv, sizeof(double));
    if (sizes)
        ts_free(T, sizes, T->ntri, sizeof(uint32_t));
    return st;
}

static geom_status tessellate_unscaled(const geom_nurbs_surface *surfaces, size_t n,
                                       const geom_surface_tess_options *options, geom_mesh *out,
                                       geom_error_report *report,
                                       geom_surface_tess_stats *stats, geom_diag *diag);

/* Scale before squaring: control points whose magnitude is far from 1
 * (beyond 2^+-64) are scaled by a power of two, which is exact, so the
 * tessellation of a model at 1e300 is that of the same model at 1 (same
 * triangles, errors and positions times the scale), and no square of a
 * coordinate can overflow or underflow on the way. */
geom_status geom_surface_tessellate(const geom_nurbs_surface *surfaces, size_t n,
                                    const geom_surface_tess_options *options, geom_mesh *out,
                                    geom_error_report *report, geom_surface_tess_stats *stats,
                                    geom_diag *diag)
{
    double maxabs = 0.0;
    size_t total = 0;
    for (size_t k = 0; surfaces && k < n; ++k) {
        if (!surfaces[k].points || surfaces[k].nu == 0 || surfaces[k].nv == 0 ||
            surfaces[k].nu > SIZE_MAX / 3 / surfaces[k].nv)
            return tessellate_unscaled(surfaces, n, options, out, report, stats, diag);
        size_t np = 3 * surfaces[k].nu * surfaces[k].nv;
        for (size_t i = 0; i < np; ++i)
            if (isfinite(surfaces[k].points[i]))
                maxabs = fmax(maxabs, fabs(surfaces[k].points[i]));
        total += np;
    }
    int ex = 0;
    if (maxabs > 0.0)
        frexp(maxabs, &ex);
    if (!out || (ex >= -64 && ex <= 64))
        return tessellate_unscaled(surfaces, n, options, out, report, stats, diag);
    const geom_allocator *al = options ? options->alloc : NULL;
    size_t bytes = n * sizeof(geom_nurbs_surface);
    geom_nurbs_surface *copy = geom__alloc(al, bytes);
    double *pts = geom__alloc(al, total * sizeof(double));
    if (!copy || !pts) {
        geom__free(al, copy, bytes);
        geom__free(al, pts, total * sizeof(double));
        return geom__diag_set(diag, GEOM_ERR_NOMEM, NULL, 0, 0, "tessellate: out of memory");
    }
    size_t at = 0;
    for (size_t k = 0; k < n; ++k) {
        copy[k] = surfaces[k];
        size_t np = 3 * surfaces[k].nu * surfaces[k].nv;
        for (size_t i = 0; i < np; ++i)
            pts[at + i] = ldexp(surfaces[k].points[i], -ex);
        copy[k].points = pts + at;
        at += np;
    }
    geom_surface_tess_options o;
    if (options)
        o = *options;
    else
        memset(&o, 0, sizeof o);
    o.tolerance = ldexp(o.tolerance, -ex);
    geom_status st = tessellate_unscaled(copy, n, &o, out, report, stats, diag);
    geom__free(al, copy, bytes);
    geom__free(al, pts, total * sizeof(double));
    if (st == GEOM_OK) {
        double *p = geom_mesh_positions(out);
        size_t nv = geom_mesh_n_vertices(out);
        for (size_t i = 0; p && i < 3 * nv; ++i)
            p[i] = ldexp(p[i], ex);
        if (report) {
            report->max_error = ldexp(report->max_error, ex);
            report->mean_error = ldexp(report->mean_error, ex);
            report->tolerance = ldexp(report->tolerance, ex);
        }
    }
    return st;
}

static geom_status tessellate_unscaled(const geom_nurbs_surface *surfaces, size_t n,
                                       const geom_surface_tess_options *options, geom_mesh *out,
                                       geom_error_report *report,
                                       geom_surface_tess_stats *stats, geom_diag *diag)
{
    double t0 = geom__seconds();
    geom_surface_tess_options defaults;
    memset(&defaults, 0, sizeof defaults);
    const geom_surface_tess_options *o = options ? options : &defaults;
    if (report)
        memset(report, 0, sizeof *report);
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (!surfaces || n == 0 || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "tessellate: NULL surfaces or mesh, or no surface");
    if (o->mode != GEOM_SURFACE_TESS_ADAPTIVE && o->mode != GEOM_SURFACE_TESS_UNIFORM)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "tessellate: unknown mode %d", (int)o->mode);
    if (!isfinite(o->tolerance) || o->tolerance < 0.0 || !isfinite(o->angle_degrees) ||
        o->angle_degrees < 0.0 || o->grid_u < 0 || o->grid_v < 0 ||
        o->grid_u > (int)MAX_GRID || o->grid_v > (int)MAX_GRID || o->check_subdivisions < 0 ||
        o->check_subdivisions > 64)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "tessellate: an option is negative, not finite or too large");
    if (n >= NONE32 / 8)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0, "tessellate: too many surfaces");
    geom_aabb box = geom_aabb_empty();
    size_t work = 0;
    for (size_t k = 0; k < n; ++k) {
        geom_diag d;
        geom_diag_clear(&d);
        if (geom_surface_validate(&surfaces[k], &d) != GEOM_OK)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "tessellate: surface %zu: %s", k, d.message);
        const geom_nurbs_surface *s = &surfaces[k];
        for (size_t i = 0; i < s->nu * s->nv; ++i)
            box = geom_aabb_extend(box, geom_vec3_make(s->points[3 * i], s->points[3 * i + 1],
                                                       s->points[3 * i + 2]));
        size_t w = geom__surface_normal_work(s);
        if (w > work)
            work = w;
    }
    double diagl = 0.0; /* the box's diagonal, without overflow near DBL_MAX */
    if (!geom_aabb_is_empty(box)) {
        double lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
        diagl = dist3(hi, lo);
    }
    double maxabs = 0.0;
    if (!geom_aabb_is_empty(box))
        maxabs = fmax(fmax(fmax(fabs(box.min.x), fabs(box.max.x)),
                           fmax(fabs(box.min.y), fabs(box.max.y))),
                      fmax(fabs(box.min.z), fabs(box.max.z)));
    ts T;
    memset(&T, 0, sizeof T);
    T.alloc = o->alloc;
    T.opt = o;
    T.diag = diag;
    T.adaptive = o->mode == GEOM_SURFACE_TESS_ADAPTIVE;
    T.tol = o->tolerance > 0.0 ? o->tolerance : 1e-3 * diagl;
    if (!(T.tol > 0.0))
        T.tol = DBL_MIN;
    /* welding: the model's size, and the resolution of its coordinates */
    T.weld_tol = 1e-9 * diagl + 256.0 * DBL_EPSILON * maxabs;
    T.ang_tol = T.adaptive ? o->angle_degrees : 0.0;
    T.normal_weld = o->normal_weld_degrees < 0.0   ? 0.0
                    : o->normal_weld_degrees > 0.0 ? o->normal_weld_degrees * (GEOM_PI / 180.0)
                                                   : GEOM_SURFACE_NORMAL_WELD_DEFAULT * (GEOM_PI / 180.0);
    T.ksub = o->check_subdivisions ? o->check_subdivisions : 4;
    T.max_tri = o->max_triangles ? o->max_triangles : ((size_t)1 << 24);
    T.pn.ncomp = 3;
    T.puv.ncomp = 2;
    T.pt.ncomp = 4;
    unsigned attrs = o->attributes &
                     (GEOM_SURFACE_ATTR_NORMAL | GEOM_SURFACE_ATTR_UV | GEOM_SURFACE_ATTR_TANGENT);
    size_t pass_tris = 0; /* triangles of the last pass */
    geom_status st = geom__scratch_init(&T.sc, work);
    T.lat = ts_alloc(&T, 3 * (size_t)(T.ksub + 1) * (size_t)(T.ksub + 2) / 2, sizeof(double));
    T.memo = ts_alloc(&T, MEMO_SIZE, sizeof(ts_memo)); /* optional: NULL evaluates every sample */
    if (T.memo)
        memset(T.memo, 0, MEMO_SIZE * sizeof(ts_memo));
    if (st == GEOM_OK && !T.lat)
        st = GEOM_ERR_NOMEM;
    if (st != GEOM_OK)
        goto fail;
    st = build_structure(&T, surfaces, n);
    if (st == GEOM_OK)
        st = weld(&T, stats);
    if (st == GEOM_OK)
        st = orient(&T, stats);
    if (st != GEOM_OK)
        goto fail;
    if (T.adaptive && T.ang_tol == 0.0) {
        st = build_warps(&T);
        if (st != GEOM_OK)
            goto fail;
    }
    /* initial demands */
    uint32_t gu = o->grid_u ? (uint32_t)o->grid_u : 8, gv = o->grid_v ? (uint32_t)o->grid_v : 8;
    for (size_t i = 0; i < T.ncells; ++i) {
        ts_cell *c = &T.cells[i];
        if (T.adaptive) {
            size_cell(&T, c);
        } else {
            c->M = gu;
            c->N = gv;
        }
    }
    size_t passes = 0;
    int optimised = 0, converged = 0;
    for (;;) {
        double est = 0.0;
        int over = 0;
        for (size_t i = 0; i < T.ncells; ++i) {
            est += 2.0 * (double)T.cells[i].M * (double)T.cells[i].N;
            over |= T.cells[i].M > MAX_GRID || T.cells[i].N > MAX_GRID;
        }
        if (over || est > (double)T.max_tri) {
            st = geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0,
                               "tessellate: the tolerance needs more than %zu triangles (or "
                               "more than %u quads along a cell)",
                               T.max_tri, MAX_GRID);
            goto fail;
        }
        st = assign_vertices(&T);
        if (st != GEOM_OK)
            goto fail;
        int failing = 0;
        pass_tris = 0;
        for (size_t i = 0; i < T.ncells; ++i) {
            ts_cell *c = &T.cells[i];
            st = retriangulate(&T, c);
            if (st != GEOM_OK)
                goto fail;
            pass_tris += T.nltri;
            if (T.adaptive && (c->err > T.tol || (T.ang_tol > 0.0 && c->ang > T.ang_tol)))
                failing = 1;
            if (o->progress)
                o->progress(o->progress_user, (double)(i + 1) / (double)T.ncells);
        }
        passes++;
        /* First pass, adaptive: the sizing bound is conservative (a sphere
         * cell sized for 1e-4 measures about 6e-5), so a cell well under
         * the tolerance is coarsened once toward COARSEN_TARGET of it (the
         * chordal error goes as the step squared) and checked again; cells
         * the coarsening pushes over are refined below. Without this the
         * result could need up to 1.5x the triangles of a uniform grid that
         * meets the same tolerance. */
        int coarsened = 0;
        if (T.adaptive && passes == 1) {
            for (size_t i = 0; i < T.ncells; ++i) {
                ts_cell *c = &T.cells[i];
                if (!(c->err < 0.8 * T.tol) || !(c->err > 0.0) ||
                    (T.ang_tol > 0.0 && !(c->ang < 0.8 * T.ang_tol)))
                    continue;
                double f = sqrt(c->err / (COARSEN_TARGET * T.tol));
                if (T.ang_tol > 0.0 && c->ang > 0.0)
                    f = fmax(f, c->ang / (COARSEN_TARGET * T.ang_tol));
                f = fmax(f, 0.25);
                uint32_t M = (uint32_t)fmax(1.0, ceil((double)c->M * f));
                uint32_t N = (uint32_t)fmax(1.0, ceil((double)c->N * f));
                if (M != c->M || N != c->N) {
                    c->M = M;
                    c->N = N;
                    coarsened = 1;
                }
            }
        }
        if (T.adaptive && !failing && !coarsened && !optimised && T.ang_tol == 0.0
            && passes < MAX_PASSES) {
            /* converged: each cell takes its smallest passing grid, and the
             * next pass checks the result as it is stitched */
            for (size_t i = 0; i < T.ncells; ++i) {
                st = optimise_cell(&T, &T.cells[i]);
                if (st != GEOM_OK)
                    goto fail;
            }
            optimised = 1;
            continue;
        }
        converged = !failing && !coarsened;
        if (converged || !T.adaptive || passes >= MAX_PASSES)
            break;
        for (size_t i = 0; i < T.ncells; ++i) {
            ts_cell *c = &T.cells[i];
            double f = 1.0;
            if (c->err > T.tol)
                f = fmax(f, 1.05 * sqrt(c->err / T.tol));
            if (T.ang_tol > 0.0 && c->ang > T.ang_tol)
                f = fmax(f, 1.05 * c->ang / T.ang_tol);
            if (f <= 1.0)
                continue;
            /* the smallest step that can pass: at least one more segment
             * (a larger minimum factor overshoots: 1.25 in both directions
             * is 1.56x the triangles) */
            f = fmin(f, 4.0);
            c->M = (uint32_t)fmin(fmax(ceil((double)c->M * f), (double)c->M + 1.0),
                                  (double)MAX_GRID + 1);
            c->N = (uint32_t)fmin(fmax(ceil((double)c->N * f), (double)c->N + 1.0),
                                  (double)MAX_GRID + 1);
            if (stats)
                stats->refinements++;
        }
    }
    /* the best uniform grid instead, when it has fewer triangles */
    if (T.adaptive && converged && T.ang_tol == 0.0) {
        int chosen;
        uint32_t bu, bv;
        st = uniform_search(&T, pass_tris, &chosen, &bu, &bv);
        if (st != GEOM_OK)
            goto fail;
        if (chosen && stats)
            stats->uniform_u = bu, stats->uniform_v = bv;
    }
    /* final pass: the same triangulation, with the attributes, and the
     * error summary of exactly these triangles */
    st = assign_vertices(&T);
    if (st != GEOM_OK)
        goto fail;
    double emax = 0.0, esum = 0.0;
    size_t ecount = 0;
    for (size_t i = 0; i < T.ncells; ++i) {
        ts_cell *c = &T.cells[i];
        st = retriangulate(&T, c);
        if (st != GEOM_OK)
            goto fail;
        emax = fmax(emax, c->err);
        if (c->ecnt) /* weighted running mean of the cells' means */
            esum += (c->esum - esum) * ((double)c->ecnt / (double)(ecount + c->ecnt));
        ecount += c->ecnt;
        if (o->progress)
            o->progress(o->progress_user, (double)(i + 1) / (double)T.ncells);
        st = emit_cell(&T, c, attrs, o->uv_normalized);
        if (st == GEOM_ERR_LIMIT)
            st = geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0,
                               "tessellate: more than %zu triangles", T.max_tri);
        if (st != GEOM_OK)
            goto fail;
    }
    st = build_mesh(&T, out, attrs, diag);
    if (st != GEOM_OK)
        goto fail;
    if (report) {
        report->max_error = emax;
        report->mean_error = ecount ? esum : 0.0;
        report->method = GEOM_ERROR_SAMPLED;
        report->evaluations = T.evals;
        report->tolerance = T.adaptive ? T.tol : 0.0; /* uniform grids have none */
        report->pieces = ecount;
        report->seconds = geom__seconds() - t0;
    }
    if (stats) {
        stats->cells = T.ncells;
        stats->triangles = geom_mesh_n_faces(out);
        stats->vertices = geom_mesh_n_vertices(out);
        stats->limit_normals = T.limit_normals;
        stats->welded_normals = T.welded_normals;
        for (size_t i = 0; i < T.nedges; ++i) {
            const ts_edge *e = &T.edges[i];
            stats->boundary_edges += e->boundary && !e->collapsed && e->partner == NONE32;
        }
    }
    ts_release(&T);
    return GEOM_OK;
fail:
    if (st == GEOM_ERR_NOMEM)
        geom__diag_set(diag, st, NULL, 0, 0, "tessellate: out of memory");
    ts_release(&T);
    return st;
}
