/*
 * One cell of the topologically correct marching cubes: the contours of the
 * trilinear interpolant on the six faces (asymptotic decider on ambiguous
 * faces), their grouping into surface components from the connectivity of
 * the interpolant's sign regions inside the cell (a sweep through the
 * planes z = t), and the triangulation of each component: a disk (one
 * contour) or a tube (two contours joined by a tunnel).
 *
 * Why grouping contours by regions gives the topology: inside the cell (a
 * ball B) the level set S of the trilinear interpolant F has no closed
 * component (F is harmonic, so it has no interior extremum), and B \ S
 * splits into sign regions each touching the cell's surface. The contours
 * cut the cell's surface into patches, each lying in one region. The
 * regions and the components of S form a tree (B is simply connected):
 * every component of S separates exactly two regions, and its boundary
 * consists of the contours between patches of those two regions. So once
 * we know which patches are joined through the interior, the components of
 * S are the classes of contours with the same pair (inside region, outside
 * region). For the trilinear interpolant such a class is a disk (one
 * contour) or a tube (two contours, a "tunnel"); components are genus 0.
 */
#include "iso/iso_internal.h"

#include <float.h>
#include <string.h>

const uint8_t geom__iso_edge_corners[12][2] = {
    {0, 1}, {2, 3}, {4, 5}, {6, 7}, /* along x */
    {0, 2}, {1, 3}, {4, 6}, {5, 7}, /* along y */
    {0, 4}, {1, 5}, {2, 6}, {3, 7}  /* along z */
};

const uint8_t geom__iso_face_corners[6][4] = {
    {0, 4, 6, 2}, /* x = 0 */
    {1, 3, 7, 5}, /* x = 1 */
    {0, 1, 5, 4}, /* y = 0 */
    {2, 6, 7, 3}, /* y = 1 */
    {0, 2, 3, 1}, /* z = 0 */
    {4, 5, 7, 6}  /* z = 1 */
};

static int edge_between(int a, int b)
{
    int lo = a < b ? a : b;
    int d = a ^ b;
    if (d == 1)
        return lo >> 1;
    if (d == 2)
        return 4 + (lo & 1) + ((lo >> 2) << 1);
    return 8 + (lo & 3);
}

int geom__iso_face_decider(double g00, double g10, double g01, double g11)
{
    /* Sign of the bilinear interpolant at its saddle relative to the
     * isovalue: (g00 g11 - g10 g01) / (g00 + g11 - g10 - g01). On an
     * ambiguous face the denominator has the sign of g00, so the corners 00
     * and 11 are joined exactly when q = g00 g11 - g10 g01 > 0 (whatever
     * their sign). q is computed with an exact sign (orient2d of (g00, g10),
     * (g01, g11) and the origin), the same in both cells sharing the face.
     * For the perturbed level, each g becomes g - eps:
     * q(eps) = q - eps (g00 + g11 - g10 - g01), so q == 0 is decided by the
     * sign of -(g00 + g11 - g10 - g01) (which has no cancellation: its two
     * pair sums have opposite signs on an ambiguous face). */
    /* an exact power-of-two scaling keeps every product in range */
    double m = fmax(fmax(fabs(g00), fabs(g10)), fmax(fabs(g01), fabs(g11)));
    int ex = 0;
    if (m > 0 && isfinite(m))
        frexp(m, &ex);
    g00 = ldexp(g00, -ex), g10 = ldexp(g10, -ex), g01 = ldexp(g01, -ex), g11 = ldexp(g11, -ex);
    const double a[2] = {g00, g10};
    const double b[2] = {g01, g11};
    const double o[2] = {0.0, 0.0};
    double q = geom_orient2d(a, b, o);
    if (q > 0)
        return 1;
    if (q < 0)
        return 0;
    return ((g00 + g11) - (g10 + g01)) < 0;
}

int geom__iso_face_inside(int f, const double g[8], int in[4], int *changes)
{
    const uint8_t *p = geom__iso_face_corners[f];
    int n = 0, c = 0;
    for (int k = 0; k < 4; k++) {
        in[k] = !(g[p[k]] > 0);
        n += in[k];
    }
    for (int k = 0; k < 4; k++)
        c += in[k] != in[(k + 1) & 3];
    *changes = c;
    return n;
}

int geom__iso_face_join(int f, const double g[8], int joined[2])
{
    int axis = f >> 1, side = f & 1;
    int au = axis == 0 ? 1 : 0;
    int av = axis == 2 ? 1 : 2;
    int c00 = side << axis;
    int c10 = c00 | (1 << au), c01 = c00 | (1 << av), c11 = c10 | (1 << av);
    int d = geom__iso_face_decider(g[c00], g[c10], g[c01], g[c11]);
    joined[0] = d ? c00 : c10;
    joined[1] = d ? c11 : c01;
    return !(g[joined[0]] > 0);
}

/* ------------------------------------------------------------ union-find */

#define UF_MAX 64

typedef struct uf {
    uint32_t parent[UF_MAX]; /* core's union-find (core/unionfind.c) */
} uf;

static void uf_init(uf *u, int n) { geom__uf_init(u->parent, (size_t)n); }
static int uf_find(uf *u, int a) { return (int)geom__uf_find(u->parent, (uint32_t)a); }
static void uf_union(uf *u, int a, int b) { geom__uf_union(u->parent, (uint32_t)a, (uint32_t)b); }

/* ------------------------------------------------------------ the sweep */

static void sort_small(double *t, int n)
{
    for (int i = 1; i < n; i++) {
        double v = t[i];
        int j = i - 1;
        while (j >= 0 && t[j] > v) {
            t[j + 1] = t[j];
            j--;
        }
        t[j + 1] = v;
    }
}

/* Roots in (0, 1) of A t^2 + B t + C, appended to t. */
static int quad_roots01(double A, double B, double C, double *t)
{
    int n = 0;
    double scale = fabs(A) + fabs(B) + fabs(C);
    if (scale == 0 || !isfinite(scale))
        return 0;
    if (fabs(A) <= 1e-14 * scale) {
        if (B != 0) {
            double r = -C / B;
            if (r > 0 && r < 1)
                t[n++] = r;
        }
        return n;
    }
    double disc = B * B - 4 * A * C;
    if (disc < 0)
        return 0;
    double sq = sqrt(disc);
    double qq = -0.5 * (B + (B >= 0 ? sq : -sq));
    double r1 = qq / A;
    double r2 = qq != 0 ? C / qq : r1;
    if (r1 > 0 && r1 < 1)
        t[n++] = r1;
    if (r2 > 0 && r2 < 1 && r2 != r1)
        t[n++] = r2;
    return n;
}

/*
 * Join, in u, the corners connected by a sign region through the cell's
 * interior. Slices z = t: F restricted to a slice is bilinear with corner
 * values g_k(t) = (1 - t) g[k] + t g[k + 4] (k = x + 2y); each sign region of
 * the slice contains a corner (a bilinear function has no interior
 * extremum), adjacent corners of equal sign are joined along their edge and
 * an ambiguous slice joins the diagonal (0, 3) when
 * q(t) = g_0 g_3 - g_1 g_2 > 0, else (1, 2). The slice topology changes only
 * at roots of the g_k and of the quadratic q, so it is constant on the open
 * intervals between them; a slice corner keeps its region across an event
 * when it keeps its sign. Nodes: 0..7 the cube corners (the slices t = 0 and
 * t = 1), 8 + 4 i + k corner k of interval i.
 */
static void sweep_join(const double g0[8], uf *u)
{
    /* scale by a power of two: the quadratic's coefficients stay finite */
    double m = 0, g[8];
    for (int c = 0; c < 8; c++)
        m = fmax(m, fabs(g0[c]));
    int ex = 0;
    if (m > 0 && isfinite(m))
        frexp(m, &ex);
    for (int c = 0; c < 8; c++)
        g[c] = ldexp(g0[c], -ex);
    double t[8];
    int ne = 0;
    for (int k = 0; k < 4; k++) {
        double a = g[k], b = g[k + 4];
        if ((a > 0) != (b > 0)) {
            double r = a / (a - b);
            if (r > 0 && r < 1)
                t[ne++] = r;
        }
    }
    double a0 = g[0], a1 = g[1], a2 = g[2], a3 = g[3];
    double d0 = g[4] - g[0], d1 = g[5] - g[1], d2 = g[6] - g[2], d3 = g[7] - g[3];
    double A = d0 * d3 - d1 * d2;
    double B = a0 * d3 + d0 * a3 - a1 * d2 - d1 * a2;
    double C = a0 * a3 - a1 * a2;
    ne += quad_roots01(A, B, C, t + ne);
    sort_small(t, ne);

    int prev[4];
    int prev_s[4];
    for (int k = 0; k < 4; k++) {
        prev[k] = k;
        prev_s[k] = g[k] > 0;
    }
    double lo = 0;
    int interval = 0;
    for (int e = 0; e <= ne; e++) {
        double hi = e < ne ? t[e] : 1.0;
        if (!(hi > lo))
            continue;
        double m = 0.5 * (lo + hi);
        double v[4];
        int s[4], cur[4];
        for (int k = 0; k < 4; k++) {
            v[k] = (1 - m) * g[k] + m * g[k + 4];
            s[k] = v[k] > 0;
            cur[k] = 8 + 4 * interval + k;
        }
        static const int adj[4][2] = {{0, 1}, {0, 2}, {1, 3}, {2, 3}};
        for (int a = 0; a < 4; a++)
            if (s[adj[a][0]] == s[adj[a][1]])
                uf_union(u, cur[adj[a][0]], cur[adj[a][1]]);
        if (s[0] == s[3] && s[1] == s[2] && s[0] != s[1]) {
            if (geom__iso_face_decider(v[0], v[1], v[2], v[3]))
                uf_union(u, cur[0], cur[3]);
            else
                uf_union(u, cur[1], cur[2]);
        }
        for (int k = 0; k < 4; k++) {
            if (s[k] == prev_s[k])
                uf_union(u, prev[k], cur[k]);
            prev[k] = cur[k];
            prev_s[k] = s[k];
        }
        interval++;
        lo = hi;
    }
    for (int k = 0; k < 4; k++)
        if ((g[k + 4] > 0) == prev_s[k])
            uf_union(u, prev[k], k + 4);
}

/* --------------------------------------------------------- triangulation */

static void emit(iso_cell_result *out, int a, int b, int c)
{
    if (out->ntris >= ISO_CELL_MAX_TRIS)
        return;
    out->tris[out->ntris][0] = (uint8_t)a;
    out->tris[out->ntris][1] = (uint8_t)b;
    out->tris[out->ntris][2] = (uint8_t)c;
    out->ntris++;
}

/* Faces (bits) containing each edge; inner vertices lie on no face. */
static const uint8_t edge_face_bits[12] = {
    /* x edges: (y, z) */ (1u << 2) | (1u << 4), (1u << 3) | (1u << 4),
    (1u << 2) | (1u << 5), (1u << 3) | (1u << 5),
    /* y edges: (x, z) */ (1u << 0) | (1u << 4), (1u << 1) | (1u << 4),
    (1u << 0) | (1u << 5), (1u << 1) | (1u << 5),
    /* z edges: (x, y) */ (1u << 0) | (1u << 2), (1u << 1) | (1u << 2),
    (1u << 0) | (1u << 3), (1u << 1) | (1u << 3)};

static unsigned ref_faces(int r)
{
    return r < 12 ? edge_face_bits[r] : 0u;
}

static const double *ref_pos(const iso_cell_result *out, const double vpos[12][3], int r)
{
    return r < 12 ? vpos[r] : out->inner[r - 12];
}

/* Squared norm of twice the area vector. (Polygons here are contours:
 * their vertices lie strictly inside distinct cell edges, and no three such
 * points are collinear, since a line meets the cube's surface in two points
 * unless it lies in a face, where each edge holds one point: no degenerate
 * triangle can be chosen.) */
static inline double tri_cost2(const double *p, const double *q, const double *r)
{
    double u0 = q[0] - p[0], u1 = q[1] - p[1], u2 = q[2] - p[2];
    double v0 = r[0] - p[0], v1 = r[1] - p[1], v2 = r[2] - p[2];
    double c0 = u1 * v2 - u2 * v1, c1 = u2 * v0 - u0 * v2, c2 = u0 * v1 - u1 * v0;
    return c0 * c0 + c1 * c1 + c2 * c2;
}

int geom__iso_polygon_tris(int n, const double *const p[], const unsigned fm[], uint8_t (*tri)[3],
                     int *forced)
{
    *forced = 0;
    if (n < 3)
        return 0;
    if (n == 3) {
        tri[0][0] = 0, tri[0][1] = 1, tri[0][2] = 2;
        return 1;
    }
    if (n == 4) {
        /* the shorter diagonal, 0-2 or 1-3, unless it lies in a cell face.
         * (No three crossing points are collinear: a line meets the cube's
         * surface twice unless it lies in a face, and a face's edges hold
         * one point each, strictly inside; so neither choice degenerates.) */
        double a = 0, b = 0;
        for (int k = 0; k < 3; k++) {
            a += (p[2][k] - p[0][k]) * (p[2][k] - p[0][k]);
            b += (p[3][k] - p[1][k]) * (p[3][k] - p[1][k]);
        }
        if (fm[0] & fm[2])
            a = HUGE_VAL;
        if (fm[1] & fm[3])
            b = HUGE_VAL;
        *forced = a == HUGE_VAL && b == HUGE_VAL;
        if (a <= b) {
            tri[0][0] = 0, tri[0][1] = 1, tri[0][2] = 2;
            tri[1][0] = 0, tri[1][1] = 2, tri[1][2] = 3;
        } else {
            tri[0][0] = 1, tri[0][1] = 2, tri[0][2] = 3;
            tri[1][0] = 1, tri[1][1] = 3, tri[1][2] = 0;
        }
        return 2;
    }
    if (n == 5 || n == 6) {
        /* every triangulation of a pentagon (5) or hexagon (14), listed by
         * the recursion "the side (0, n-1) lies in a triangle (0, k, n-1),
         * then triangulate both sides"; priced as below */
        static const uint8_t t5[5][3][3] = {
            {{2, 3, 4}, {1, 2, 4}, {0, 1, 4}}, {{1, 2, 3}, {1, 3, 4}, {0, 1, 4}},
            {{0, 1, 2}, {2, 3, 4}, {0, 2, 4}}, {{1, 2, 3}, {0, 1, 3}, {0, 3, 4}},
            {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}};
        static const uint8_t t6[14][4][3] = {
            {{3, 4, 5}, {2, 3, 5}, {1, 2, 5}, {0, 1, 5}},
            {{2, 3, 4}, {2, 4, 5}, {1, 2, 5}, {0, 1, 5}},
            {{1, 2, 3}, {3, 4, 5}, {1, 3, 5}, {0, 1, 5}},
            {{2, 3, 4}, {1, 2, 4}, {1, 4, 5}, {0, 1, 5}},
            {{1, 2, 3}, {1, 3, 4}, {1, 4, 5}, {0, 1, 5}},
            {{0, 1, 2}, {3, 4, 5}, {2, 3, 5}, {0, 2, 5}},
            {{0, 1, 2}, {2, 3, 4}, {2, 4, 5}, {0, 2, 5}},
            {{1, 2, 3}, {0, 1, 3}, {3, 4, 5}, {0, 3, 5}},
            {{0, 1, 2}, {0, 2, 3}, {3, 4, 5}, {0, 3, 5}},
            {{2, 3, 4}, {1, 2, 4}, {0, 1, 4}, {0, 4, 5}},
            {{1, 2, 3}, {1, 3, 4}, {0, 1, 4}, {0, 4, 5}},
            {{0, 1, 2}, {2, 3, 4}, {0, 2, 4}, {0, 4, 5}},
            {{1, 2, 3}, {0, 1, 3}, {0, 3, 4}, {0, 4, 5}},
            {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}}};
        double c3[6][6][6];
        for (int i = 0; i < n; i++)
            for (int k = i + 1; k < n; k++)
                for (int j = k + 1; j < n; j++) {
                    double c = tri_cost2(p[i], p[k], p[j]);
                    /* chords (non-sides) lying in a cell face */
                    if (k != i + 1 && (fm[i] & fm[k]))
                        c += 1e30;
                    if (j != k + 1 && (fm[k] & fm[j]))
                        c += 1e30;
                    if (!(i == 0 && j == n - 1) && (fm[i] & fm[j]))
                        c += 1e30;
                    c3[i][k][j] = c;
                }
        int count = n == 5 ? 5 : 14, m = n - 2, best = 0;
        double bc = HUGE_VAL;
        for (int q = 0; q < count; q++) {
            const uint8_t(*t)[3] = n == 5 ? t5[q] : t6[q];
            double c = 0;
            for (int r = 0; r < m; r++)
                c += c3[t[r][0]][t[r][1]][t[r][2]];
            if (c < bc) {
                bc = c;
                best = q;
            }
        }
        *forced = bc >= 1e30;
        const uint8_t(*t)[3] = n == 5 ? t5[best] : t6[best];
        for (int r = 0; r < m; r++) {
            /* listed as (i, k, j) with i < k < j: polygon order, so the
             * orientation is kept */
            tri[r][0] = t[r][0], tri[r][1] = t[r][1], tri[r][2] = t[r][2];
        }
        return m;
    }
    /* Triangulation minimising the sum of squared triangle areas (close to
     * the minimum-area one, and cheaper), by dynamic programming over the
     * chords (each triangle (i, k, j) is priced once); chords lying in a
     * cell face are penalised. */
    enum { M = ISO_POLY_MAX };
    if (n > M)
        n = M;
    double cost[M][M];
    uint8_t split[M][M];
    for (int i = 0; i + 1 < n; i++)
        cost[i][i + 1] = 0;
    for (int len = 2; len < n; len++) {
        for (int i = 0; i + len < n; i++) {
            int j = i + len;
            double chord = (!(i == 0 && j == n - 1) && (fm[i] & fm[j])) ? 1e30 : 0.0;
            double best = HUGE_VAL;
            int bk = i + 1;
            for (int k = i + 1; k < j; k++) {
                double c = cost[i][k] + cost[k][j] + tri_cost2(p[i], p[k], p[j]);
                if (c < best) {
                    best = c;
                    bk = k;
                }
            }
            cost[i][j] = best + chord;
            split[i][j] = (uint8_t)bk;
        }
    }
    *forced = cost[0][n - 1] >= 1e30;
    int stack[M][2];
    int sp = 0, nt = 0;
    stack[sp][0] = 0;
    stack[sp][1] = n - 1;
    sp++;
    while (sp > 0) {
        sp--;
        int i = stack[sp][0], j = stack[sp][1];
        if (j - i < 2)
            continue;
        int k = split[i][j];
        tri[nt][0] = (uint8_t)i, tri[nt][1] = (uint8_t)k, tri[nt][2] = (uint8_t)j;
        nt++;
        stack[sp][0] = i;
        stack[sp][1] = k;
        sp++;
        stack[sp][0] = k;
        stack[sp][1] = j;
        sp++;
    }
    return nt;
}

/* The cell being triangulated: corner values and placement, for inner
 * vertices. */
typedef struct cell_ctx {
    const double *g; /* 8 corner values */
    const double *lo, *size;
    const double (*vpos)[3];
} cell_ctx;

static double trilinear_at(const double *g, const double u[3], double grad[3])
{
    double x = u[0], y = u[1], z = u[2];
    double a = g[0] + x * (g[1] - g[0]), b = g[2] + x * (g[3] - g[2]);
    double c = g[4] + x * (g[5] - g[4]), d = g[6] + x * (g[7] - g[6]);
    double e = a + y * (b - a), f = c + y * (d - c);
    if (grad) {
        double ax = g[1] - g[0], bx = g[3] - g[2], cx = g[5] - g[4], dx = g[7] - g[6];
        double ex = ax + y * (bx - ax), fx = cx + y * (dx - cx);
        grad[0] = ex + z * (fx - ex);
        grad[1] = (b - a) + z * ((d - c) - (b - a));
        grad[2] = f - e;
    }
    return e + z * (f - e);
}

/* A new inner vertex near world point q, moved onto the level set of the
 * cell's trilinear interpolant by a few Newton steps along its gradient
 * (kept inside the cell; q itself if that fails). Returns its reference. */
static int inner_vertex(const cell_ctx *cc, iso_cell_result *out, const double q[3])
{
    if (out->ninner >= ISO_CELL_MAX_INNER)
        return -1;
    double u[3], best[3];
    /* strictly inside the cell: inner vertices of two cells never meet */
    for (int k = 0; k < 3; k++) {
        u[k] = cc->size[k] > 0 ? (q[k] - cc->lo[k]) / cc->size[k] : 0.5;
        u[k] = best[k] = fmin(fmax(u[k], 0.02), 0.98);
    }
    double scale = 0;
    for (int c = 0; c < 8; c++)
        scale = fmax(scale, fabs(cc->g[c]));
    double fb = HUGE_VAL;
    for (int it = 0; it < 8; it++) {
        double gr[3];
        double f = trilinear_at(cc->g, u, gr);
        if (fabs(f) < fb) {
            fb = fabs(f);
            best[0] = u[0], best[1] = u[1], best[2] = u[2];
        }
        double n2 = gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2];
        if (!(n2 > 0) || fabs(f) <= 1e-14 * scale)
            break;
        for (int k = 0; k < 3; k++) {
            u[k] -= f * gr[k] / n2;
            u[k] = fmin(fmax(u[k], 0.02), 0.98);
        }
    }
    double *o = out->inner[out->ninner];
    for (int k = 0; k < 3; k++)
        o[k] = cc->lo[k] + best[k] * cc->size[k];
    return 12 + out->ninner++;
}

/* Triangulation of the polygon v[0..n-1] keeping its orientation: without
 * new vertices when possible (geom__iso_polygon_tris), else (when every choice
 * would put a chord in a cell face) as a fan around an inner vertex. */
static void tri_polygon(const int *v, int n, const cell_ctx *cc, iso_cell_result *out)
{
    const double *p[ISO_POLY_MAX] = {NULL};
    unsigned fm[ISO_POLY_MAX] = {0};
    uint8_t t[ISO_POLY_MAX][3];
    if (n > ISO_POLY_MAX)
        n = ISO_POLY_MAX;
    for (int i = 0; i < n; i++) {
        p[i] = ref_pos(out, cc->vpos, v[i]);
        fm[i] = ref_faces(v[i]);
    }
    int forced;
    int nt = geom__iso_polygon_tris(n, p, fm, t, &forced);
    if (forced) {
        double q[3] = {0, 0, 0};
        for (int i = 0; i < n; i++)
            for (int k = 0; k < 3; k++)
                q[k] += p[i][k] / n;
        int c = inner_vertex(cc, out, q);
        if (c >= 0) {
            for (int i = 0; i < n; i++)
                emit(out, c, v[i], v[(i + 1) % n]);
            return;
        }
    }
    for (int q = 0; q < nt; q++)
        emit(out, v[t[q][0]], v[t[q][1]], v[t[q][2]]);
}

static double dist2(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/*
 * The zipper between the loops a (na refs, walked forward) and b (nb refs,
 * walked backward), both oriented as boundaries of the band between them,
 * from the closest pair (a[0], b[*j0]): each step advances along a or b
 * over the shorter new diagonal; a step sequence is a monotone lattice path
 * from (0, 0) to (na, nb), and the band is an annulus (no diagonal used
 * twice) exactly when the steps along a do not all happen at one position
 * on b and vice versa, which the choice enforces. steps[s] = 1 (advance a)
 * or 0 (advance b); returns the number of steps (na + nb, at most
 * ZIPPER_MAX: a cell's loops have at most 12 refs each, and a ring 10).
 */
#define ZIPPER_MAX 24
static int zipper_walk(const int *a, int na, const int *b, int nb, const double (*vpos)[3],
                       const iso_cell_result *out, int steps[ZIPPER_MAX], int *j0_out)
{
    int j0 = 0;
    double best = HUGE_VAL;
    for (int j = 0; j < nb; j++) {
        double d = dist2(ref_pos(out, vpos, a[0]), ref_pos(out, vpos, b[j]));
        if (d < best) {
            best = d;
            j0 = j;
        }
    }
    int ns = 0, ia = 0, ib = 0;
    int first_a = -1, first_b = -1; /* ib at the first a-step, ia at the first b-step */
    while ((ia < na || ib < nb) && ns < ZIPPER_MAX) {
        int i = ia % na, i1 = (ia + 1) % na;
        int j = ((j0 - ib) % nb + nb) % nb, j1 = ((j0 - ib - 1) % nb + nb) % nb;
        int can_a = ia < na && !(ia == na - 1 && first_a == ib);
        int can_b = ib < nb && !(ib == nb - 1 && first_b == ia);
        int adv_a;
        if (can_a && can_b)
            adv_a = dist2(ref_pos(out, vpos, a[i1]), ref_pos(out, vpos, b[j])) <=
                    dist2(ref_pos(out, vpos, a[i]), ref_pos(out, vpos, b[j1]));
        else if (can_a || can_b)
            adv_a = can_a;
        else
            break; /* cannot happen (see above) */
        steps[ns++] = adv_a;
        if (adv_a) {
            if (first_a < 0)
                first_a = ib;
            ia++;
        } else {
            if (first_b < 0)
                first_b = ia;
            ib++;
        }
    }
    *j0_out = j0;
    return ns;
}

/*
 * A tube between the loops a and b (as zipper_walk's): each diagonal of
 * the zipper gets an inner vertex (its midpoint moved onto the
 * interpolant's level set), and each zipper triangle is split along the
 * segment between the inner vertices of its two diagonals: the tube passes
 * through this ring, and no edge of it lies in a cell face.
 */
static void tri_tube(const int *a, int na, const int *b, int nb, const cell_ctx *cc,
                     iso_cell_result *out)
{
    const double(*vpos)[3] = cc->vpos;
    int steps[ZIPPER_MAX], j0;
    int ns = zipper_walk(a, na, b, nb, vpos, out, steps, &j0);
    /* the ring: one inner vertex per diagonal, diagonal s joining the
     * pair before step s (the last step closes onto diagonal 0) */
    int ring[ZIPPER_MAX];
    int ia = 0, ib = 0;
    for (int q = 0; q < ns; q++) {
        const double *pa = ref_pos(out, vpos, a[ia % na]);
        const double *pb = ref_pos(out, vpos, b[((j0 - ib) % nb + nb) % nb]);
        double m[3] = {0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2])};
        ring[q] = inner_vertex(cc, out, m);
        if (ring[q] < 0)
            return;
        if (steps[q])
            ia++;
        else
            ib++;
    }
    ia = ib = 0;
    for (int q = 0; q < ns; q++) {
        int i = ia % na, i1 = (ia + 1) % na;
        int j = ((j0 - ib) % nb + nb) % nb, j1 = ((j0 - ib - 1) % nb + nb) % nb;
        int m1 = ring[q], m2 = ring[(q + 1) % ns];
        if (steps[q]) {
            /* zipper triangle (a_i, a_i1, b_j), diagonals (a_i, b_j) -> m1
             * and (a_i1, b_j) -> m2 */
            emit(out, a[i], a[i1], m2);
            emit(out, a[i], m2, m1);
            emit(out, m1, m2, b[j]);
            ia++;
        } else {
            /* zipper triangle (b_j1, b_j, a_i), diagonals (a_i, b_j) -> m1
             * and (a_i, b_j1) -> m2 */
            emit(out, b[j1], b[j], m1);
            emit(out, b[j1], m1, m2);
            emit(out, m2, m1, a[i]);
            ib++;
        }
    }
}

/* The plain zipper band between loops a (forward) and b (backward), both
 * oriented as boundaries of the band (zipper_walk). */
static void zipper_band(const int *a, int na, const int *b, int nb, const double (*vpos)[3],
                        iso_cell_result *out)
{
    int steps[ZIPPER_MAX], j0;
    int ns = zipper_walk(a, na, b, nb, vpos, out, steps, &j0);
    int ia = 0, ib = 0;
    for (int q = 0; q < ns; q++) {
        int i = ia % na, i1 = (ia + 1) % na;
        int j = ((j0 - ib) % nb + nb) % nb, j1 = ((j0 - ib - 1) % nb + nb) % nb;
        if (steps[q]) {
            emit(out, a[i], a[i1], b[j]);
            ia++;
        } else {
            emit(out, b[j1], b[j], a[i]);
            ib++;
        }
    }
}

static void centroid(const int *v, int n, const double (*vpos)[3], const iso_cell_result *out,
                     double c[3])
{
    c[0] = c[1] = c[2] = 0;
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            c[k] += ref_pos(out, vpos, v[i])[k] / n;
}

static double field_at(const cell_ctx *cc, const double x[3])
{
    double u[3];
    for (int k = 0; k < 3; k++)
        u[k] = cc->size[k] > 0 ? (x[k] - cc->lo[k]) / cc->size[k] : 0.0;
    return trilinear_at(cc->g, u, NULL);
}

/* The ring of nr points where rays from m in the plane through m normal to
 * d (unit) first leave the core (sign core_out) inside the cell; 0 when some
 * ray meets no wall before the cell's boundary, unless lenient (then that
 * ray's point stops just short of the boundary). */
static int ring_in_plane(const cell_ctx *cc, int core_out, const double m[3], const double d[3],
                         int nr, int lenient, double ring[][3])
{
    /* basis of the plane: u perpendicular to d, v = d x u */
    double u[3], v[3];
    int ax = fabs(d[0]) < fabs(d[1]) ? (fabs(d[0]) < fabs(d[2]) ? 0 : 2)
                                     : (fabs(d[1]) < fabs(d[2]) ? 1 : 2);
    double e[3] = {0, 0, 0};
    e[ax] = 1;
    double ed = e[0] * d[0] + e[1] * d[1] + e[2] * d[2], ul = 0;
    for (int k = 0; k < 3; k++) {
        u[k] = e[k] - ed * d[k];
        ul += u[k] * u[k];
    }
    ul = sqrt(ul);
    for (int k = 0; k < 3; k++)
        u[k] /= ul;
    v[0] = d[1] * u[2] - d[2] * u[1];
    v[1] = d[2] * u[0] - d[0] * u[2];
    v[2] = d[0] * u[1] - d[1] * u[0];
    for (int r = 0; r < nr; r++) {
        double th = 2 * GEOM_PI * r / nr;
        double dir[3];
        for (int k = 0; k < 3; k++)
            dir[k] = cos(th) * u[k] + sin(th) * v[k];
        /* distance to the cell's boundary along dir */
        double tmax = HUGE_VAL;
        for (int k = 0; k < 3; k++) {
            if (dir[k] > 1e-12)
                tmax = fmin(tmax, (cc->lo[k] + cc->size[k] - m[k]) / dir[k]);
            else if (dir[k] < -1e-12)
                tmax = fmin(tmax, (cc->lo[k] - m[k]) / dir[k]);
        }
        if (!(tmax > 0) || !isfinite(tmax))
            return 0;
        tmax *= 0.98; /* stay strictly inside the cell */
        double t0 = 0, t1 = -1;
        enum { STEPS = 24 };
        for (int q = 1; q <= STEPS; q++) {
            double t = tmax * q / STEPS, x[3];
            for (int k = 0; k < 3; k++)
                x[k] = m[k] + t * dir[k];
            if ((field_at(cc, x) > 0) != core_out) {
                t1 = t;
                break;
            }
            t0 = t;
        }
        if (t1 < 0) {
            if (!lenient)
                return 0; /* the wall is not inside the cell in this direction */
            t0 = t1 = tmax; /* the core reaches the boundary: stop short of it */
        }
        for (int it = 0; it < 40 && t1 > t0; it++) {
            double t = 0.5 * (t0 + t1), x[3];
            for (int k = 0; k < 3; k++)
                x[k] = m[k] + t * dir[k];
            if ((field_at(cc, x) > 0) == core_out)
                t0 = t;
            else
                t1 = t;
        }
        for (int k = 0; k < 3; k++)
            ring[r][k] = m[k] + 0.5 * (t0 + t1) * dir[k];
    }
    return 1;
}

/*
 * A tube between loops a and b around the tunnel's core, whose sign is
 * core_out (1: the core is outside, F > 0; 0: inside): a ring in the plane
 * half-way between the loops' centroids, perpendicular to the line joining
 * them, whose vertices are where rays from the axis first leave the core
 * (bisection on the interpolant); then one zipper band from each loop to
 * the ring. Returns 0 (nothing emitted) when the ring cannot be found that
 * way.
 */
static int tri_tube_ring(const int *a, int na, const int *b, int nb, int core_out, int variant,
                         const cell_ctx *cc, iso_cell_result *out)
{
    const double(*vpos)[3] = cc->vpos;
    double ca[3], cb[3], d[3], m[3];
    centroid(a, na, vpos, out, ca);
    centroid(b, nb, vpos, out, cb);
    double dl = 0;
    for (int k = 0; k < 3; k++) {
        d[k] = cb[k] - ca[k];
        dl += d[k] * d[k];
    }
    dl = sqrt(dl);
    if (!(dl > 0))
        return 0;
    for (int k = 0; k < 3; k++)
        d[k] /= dl;
    /* a point of the core on the axis, as central as possible (variants
     * 18 and up go straight to the lattice search below) */
    static const double ts[5] = {0.5, 0.4, 0.6, 0.3, 0.7};
    int found = 0;
    for (int q = 0; q < 5 && !found && variant < 18; q++) {
        for (int k = 0; k < 3; k++)
            m[k] = ca[k] + ts[q] * (cb[k] - ca[k]);
        found = (field_at(cc, m) > 0) == core_out;
    }
    if (!found) {
        /* a bent tunnel: the core point of a lattice inside the cell
         * nearest to both loops */
        double bestd = HUGE_VAL;
        enum { L = 7 };
        for (int q = 0; q < L * L * L; q++) {
            double x[3], uu[3] = {(q % L + 0.5) / L, (q / L % L + 0.5) / L, (q / (L * L) + 0.5) / L};
            for (int k = 0; k < 3; k++)
                x[k] = cc->lo[k] + uu[k] * cc->size[k];
            if ((trilinear_at(cc->g, uu, NULL) > 0) != core_out)
                continue;
            double da = dist2(x, ca), db = dist2(x, cb), dm = da > db ? da : db;
            if (dm < bestd) {
                bestd = dm;
                m[0] = x[0], m[1] = x[1], m[2] = x[2];
                found = 1;
            }
        }
        if (!found)
            return 0;
    }
    int nr = na > nb ? na : nb;
    if (nr < 4)
        nr = 4;
    nr += 2 * (variant / 6 % 3); /* later variants: finer rings */
    if (nr > 10)
        nr = 10;
    if (out->ninner + nr > ISO_CELL_MAX_INNER)
        return 0;
    /* plane normals to try: the loops' axis, then towards each loop from
     * the core point, then the coordinate axes */
    double normals[6][3] = {{d[0], d[1], d[2]},
                            {m[0] - ca[0], m[1] - ca[1], m[2] - ca[2]},
                            {cb[0] - m[0], cb[1] - m[1], cb[2] - m[2]},
                            {1, 0, 0},
                            {0, 1, 0},
                            {0, 0, 1}};
    double ring[10][3];
    int ok = 0;
    for (int q = 0; q < 12 && !ok; q++) {
        const double *nq = normals[(q + variant) % 6];
        double nl = sqrt(nq[0] * nq[0] + nq[1] * nq[1] + nq[2] * nq[2]);
        if (!(nl > 0))
            continue;
        for (int k = 0; k < 3; k++)
            d[k] = nq[k] / nl;
        ok = ring_in_plane(cc, core_out, m, d, nr, q >= 6, ring);
    }
    if (!ok)
        return 0;
    /* The ring's direction: a band joins a loop walked forward to the ring
     * walked backward, so the ring must turn about d like b and against a:
     * the sign of (winding of b) - (winding of a) about the ring's centre.
     * Ring r runs counter-clockwise about d. */
    double sense = 0;
    for (int l = 0; l < 2; l++) {
        const int *v = l ? b : a;
        int n = l ? nb : na;
        double sl = 0;
        for (int i = 0; i < n; i++) {
            const double *p = ref_pos(out, vpos, v[i]), *q = ref_pos(out, vpos, v[(i + 1) % n]);
            double x[3] = {p[0] - m[0], p[1] - m[1], p[2] - m[2]};
            double y[3] = {q[0] - m[0], q[1] - m[1], q[2] - m[2]};
            sl += (x[1] * y[2] - x[2] * y[1]) * d[0] + (x[2] * y[0] - x[0] * y[2]) * d[1] +
                  (x[0] * y[1] - x[1] * y[0]) * d[2];
        }
        sense += l ? sl : -sl;
    }
    int r1[10], r2[10];
    for (int r = 0; r < nr; r++) {
        double *o = out->inner[out->ninner];
        o[0] = ring[r][0], o[1] = ring[r][1], o[2] = ring[r][2];
        r1[sense < 0 ? nr - 1 - r : r] = 12 + out->ninner++;
    }
    for (int r = 0; r < nr; r++)
        r2[r] = r1[nr - 1 - r];
    zipper_band(a, na, r1, nr, vpos, out);
    zipper_band(b, nb, r2, nr, vpos, out);
    return 1;
}

/* ----------------------------------------------------------- case table */

void geom__iso_case_table_init(iso_case_table *t)
{
    for (int cs = 0; cs < 256; cs++) {
        iso_case *c = &t->cases[cs];
        memset(c, 0, sizeof *c);
        if (cs == 0 || cs == 255)
            continue;
        int next[12];
        for (int e = 0; e < 12; e++)
            next[e] = -1;
        int ambiguous = 0;
        for (int f = 0; f < 6; f++) {
            const uint8_t *p = geom__iso_face_corners[f];
            int sg[4], changes = 0;
            for (int k = 0; k < 4; k++)
                sg[k] = (cs >> p[k]) & 1;
            for (int k = 0; k < 4; k++)
                changes += sg[k] != sg[(k + 1) & 3];
            if (changes == 4)
                ambiguous = 1;
            if (changes != 2)
                continue;
            int from = -1, to = -1;
            for (int k = 0; k < 4; k++) {
                int k1 = (k + 1) & 3;
                if (sg[k] && !sg[k1])
                    from = edge_between(p[k], p[k1]);
                else if (!sg[k] && sg[k1])
                    to = edge_between(p[k], p[k1]);
            }
            next[from] = to;
        }
        if (ambiguous)
            continue;
        int start = -1, count = 0;
        for (int e = 0; e < 12; e++)
            if (next[e] >= 0) {
                count++;
                if (start < 0)
                    start = e;
            }
        int n = 0, cur = start;
        do {
            c->edges[n++] = (uint8_t)cur;
            cur = next[cur];
        } while (cur != start && cur >= 0 && n < 12);
        if (n == count) { /* one contour through every crossing edge */
            c->simple = 1;
            c->n = (uint8_t)n;
        }
    }
}

/* ------------------------------------------------- local intersection check */

/* Does segment pq cross the interior of triangle abc (exact signs)? Touching
 * and coplanar configurations do not count. */
static int seg_crosses_tri(const double *p, const double *q, const double *a, const double *b,
                           const double *c)
{
    double o1 = geom_orient3d(a, b, c, p), o2 = geom_orient3d(a, b, c, q);
    if ((o1 >= 0 && o2 >= 0) || (o1 <= 0 && o2 <= 0))
        return 0;
    double s1 = geom_orient3d(p, q, a, b), s2 = geom_orient3d(p, q, b, c),
           s3 = geom_orient3d(p, q, c, a);
    return (s1 > 0 && s2 > 0 && s3 > 0) || (s1 < 0 && s2 < 0 && s3 < 0);
}

/* Whether two triangles of the cell's output cross each other (edges of
 * one through the other, beyond shared vertices). */
static int cell_self_intersects(const iso_cell_result *out, const double (*vpos)[3])
{
    for (int s = 0; s < out->ntris; s++)
        for (int t = s + 1; t < out->ntris; t++) {
            const uint8_t *A = out->tris[s], *B = out->tris[t];
            int shared = 0;
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    shared += A[i] == B[j];
            if (shared >= 2)
                continue;
            const double *pa[3], *pb[3];
            for (int i = 0; i < 3; i++) {
                pa[i] = ref_pos(out, vpos, A[i]);
                pb[i] = ref_pos(out, vpos, B[i]);
            }
            for (int k = 0; k < 3; k++) {
                int k1 = (k + 1) % 3;
                /* edges sharing a vertex with the other triangle touch it
                 * there; test them anyway only when nothing is shared */
                int ea = shared && (A[k] == B[0] || A[k] == B[1] || A[k] == B[2] ||
                                    A[k1] == B[0] || A[k1] == B[1] || A[k1] == B[2]);
                int eb = shared && (B[k] == A[0] || B[k] == A[1] || B[k] == A[2] ||
                                    B[k1] == A[0] || B[k1] == A[1] || B[k1] == A[2]);
                if (!ea && seg_crosses_tri(pa[k], pa[k1], pb[0], pb[1], pb[2]))
                    return 1;
                if (!eb && seg_crosses_tri(pb[k], pb[k1], pa[0], pa[1], pa[2]))
                    return 1;
            }
        }
    return 0;
}

/* ------------------------------------------------------------- the cell */

void geom__iso_cell_triangulate(const double g[8], const double vpos[12][3], const double lo[3],
                          const double size[3], iso_cell_result *out)
{
    out->ntris = 0;
    out->ninner = 0;
    out->ambiguous = 0;
    out->tunnels = 0;

    unsigned outside = 0;
    for (int c = 0; c < 8; c++)
        if (g[c] > 0)
            outside |= 1u << c;
    if (outside == 0 || outside == 0xFFu)
        return;

    int next[12];
    for (int e = 0; e < 12; e++)
        next[e] = -1;
    int joined[6][2];
    for (int f = 0; f < 6; f++) {
        const uint8_t *p = geom__iso_face_corners[f];
        int s[4];
        int changes = 0;
        for (int k = 0; k < 4; k++)
            s[k] = (int)((outside >> p[k]) & 1u);
        for (int k = 0; k < 4; k++)
            changes += s[k] != s[(k + 1) & 3];
        if (changes == 2) {
            int from = -1, to = -1;
            for (int k = 0; k < 4; k++) {
                int k1 = (k + 1) & 3;
                if (s[k] && !s[k1])
                    from = edge_between(p[k], p[k1]);
                else if (!s[k] && s[k1])
                    to = edge_between(p[k], p[k1]);
            }
            next[from] = to;
        } else if (changes == 4) {
            int inside_joined = geom__iso_face_join(f, g, joined[f]);
            for (int k = 0; k < 4; k++) {
                int km = (k + 3) & 3, kp = (k + 1) & 3;
                if (inside_joined && s[k])
                    next[edge_between(p[k], p[kp])] = edge_between(p[km], p[k]);
                else if (!inside_joined && !s[k])
                    next[edge_between(p[km], p[k])] = edge_between(p[k], p[kp]);
            }
            out->ambiguous |= 1u << f;
        }
    }

    /* Contours: follow next[] around each cycle. */
    int verts[12], cstart[7], clen[7], nc = 0, nv = 0;
    unsigned visited = 0;
    for (int e = 0; e < 12; e++) {
        if (next[e] < 0 || ((visited >> e) & 1u))
            continue;
        cstart[nc] = nv;
        int cur = e, steps = 0;
        while (cur >= 0 && !((visited >> cur) & 1u) && steps < 12) {
            visited |= 1u << cur;
            verts[nv++] = cur;
            cur = next[cur];
            steps++;
        }
        clen[nc] = nv - cstart[nc];
        nc++;
    }
    cell_ctx cc = {g, lo, size, vpos};
    if (nc == 1) {
        tri_polygon(verts + cstart[0], clen[0], &cc, out);
        return;
    }

    /* Regions: corners joined on the cell's surface (edges of equal sign,
     * decided faces), then through the interior. */
    uf u;
    uf_init(&u, UF_MAX);
    for (int e = 0; e < 12; e++) {
        int a = geom__iso_edge_corners[e][0], b = geom__iso_edge_corners[e][1];
        if (((outside >> a) & 1u) == ((outside >> b) & 1u))
            uf_union(&u, a, b);
    }
    for (int f = 0; f < 6; f++)
        if ((out->ambiguous >> f) & 1u)
            uf_union(&u, joined[f][0], joined[f][1]);
    uf surf = u; /* the patches: connectivity on the cell's surface only */
    sweep_join(g, &u);

    int rin[7], rout[7], group[7];
    for (int i = 0; i < nc; i++) {
        int e = verts[cstart[i]];
        int a = geom__iso_edge_corners[e][0], b = geom__iso_edge_corners[e][1];
        int in = g[a] > 0 ? b : a;
        int ou = g[a] > 0 ? a : b;
        rin[i] = uf_find(&u, in);
        rout[i] = uf_find(&u, ou);
        group[i] = i;
        for (int j = 0; j < i; j++)
            if (rin[j] == rin[i] && rout[j] == rout[i]) {
                group[i] = group[j];
                break;
            }
    }
    /* Build the pieces; when a tube is involved, check the cell's triangles
     * for crossings and retry with other ring planes and sizes. */
    int t0 = out->ntris, n0 = out->ninner;
    iso_cell_result first;
    enum { VARIANTS = 37 }; /* 36 ring variants, then the zipper-midpoint tube */
    for (int variant = 0; variant < VARIANTS; variant++) {
        out->ntris = t0;
        out->ninner = n0;
        out->tunnels = 0;
        for (int i = 0; i < nc; i++) {
            if (group[i] != i)
                continue;
            int members[7], nm = 0;
            for (int j = i; j < nc; j++)
                if (group[j] == i)
                    members[nm++] = j;
            if (nm == 2) {
                /* the tunnel's core: the region whose patches the tube
                 * joins, i.e. not the patch the two contours share */
                int pin[2], pout[2];
                for (int q = 0; q < 2; q++) {
                    int e = verts[cstart[members[q]]];
                    int a = geom__iso_edge_corners[e][0], b = geom__iso_edge_corners[e][1];
                    pin[q] = uf_find(&surf, g[a] > 0 ? b : a);
                    pout[q] = uf_find(&surf, g[a] > 0 ? a : b);
                }
                int core = pin[0] == pin[1] ? 1 : pout[0] == pout[1] ? 0 : -1;
                int ntri0 = out->ntris, ninner0 = out->ninner;
                const int *la = verts + cstart[members[0]], *lb = verts + cstart[members[1]];
                if (core < 0 || variant == VARIANTS - 1 ||
                    !tri_tube_ring(la, clen[members[0]], lb, clen[members[1]], core, variant,
                                   &cc, out)) {
                    out->ntris = ntri0;
                    out->ninner = ninner0;
                    tri_tube(la, clen[members[0]], lb, clen[members[1]], &cc, out);
                }
                out->tunnels++;
            } else {
                /* One contour: a disk. (More than two contours on one
                 * component does not occur for a trilinear interpolant;
                 * should rounding ever produce it, each contour gets its
                 * own disk, which keeps the surface manifold.) */
                for (int m = 0; m < nm; m++)
                    tri_polygon(verts + cstart[members[m]], clen[members[m]], &cc, out);
            }
        }
        if (!out->tunnels || !cell_self_intersects(out, vpos))
            return;
        if (variant == 0)
            first = *out;
    }
    *out = first; /* no variant avoids every crossing: keep the first */
}
