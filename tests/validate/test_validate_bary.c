/*
 * libgeom's exact predicates (geom_orient2d, geom_orient3d, geom_incircle)
 * and simplex barycentric coordinates (geom_bary_tri2, geom_bary_tri3,
 * geom_bary_tet) against exact rational references computed by CGAL through
 * the validation shim (geom_validate.h), on random and adversarial inputs:
 *  - random simplices and query points;
 *  - points exactly on edges (dyadic edges, axis-aligned edges) and faces,
 *    and exactly at vertices;
 *  - slivers with area / longest_edge^2 (volume / longest_edge^3) down to
 *    1e-15;
 *  - coordinates offset by 1e8; tiny simplices (1e-100 scale);
 *  - near-collinear / near-coplanar / near-cocircular point grids perturbed
 *    by single ulps (many exactly degenerate).
 * Each function gets at least 10^5 cases. Asserted: the predicates' signs
 * equal the exact signs; the status (ok / degenerate) equals the
 * reference's; every coordinate that is exactly 0 comes back exactly 0, every
 * other has the exact sign; at a vertex the result is exactly (1, 0, ...);
 * and |l_i - exact_i| <= 1e-9 * max_j |exact_j|. The worst errors seen are
 * printed (relative to max |exact| and in ulps of the coordinate itself,
 * against bary.h's "a few ulp").
 *
 * The random numbers come from a fixed-seed splitmix64, so every run sees
 * the same cases.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "geom/bary.h"
#include "geom/core.h"
#include "validate/geom_validate.h"

/* Cases per kind of input, per function; every function has >= 8 kinds. */
#define N_PER_KIND 12500

/* ------------------------------------------------------------------ PRNG */

typedef struct rng {
    uint64_t s;
} rng;

static uint64_t next_u64(rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* uniform in [0, 1), 53 random bits */
static double unif(rng *r) { return (double)(next_u64(r) >> 11) * 0x1p-53; }
/* uniform in [lo, hi) */
static double unif_in(rng *r, double lo, double hi) { return lo + (hi - lo) * unif(r); }
/* integer in [lo, hi] */
static int64_t int_in(rng *r, int64_t lo, int64_t hi)
{
    return lo + (int64_t)(next_u64(r) % (uint64_t)(hi - lo + 1));
}
/* x moved by k ulps (k may be negative) */
static double ulps(double x, int k)
{
    for (; k > 0; --k)
        x = nextafter(x, INFINITY);
    for (; k < 0; ++k)
        x = nextafter(x, -INFINITY);
    return x;
}

/* ---------------------------------------------------------- statistics */

typedef struct stats {
    size_t cases, degenerate, zeros, onvertex;
    double worst_rel; /* max |l_i - exact_i| / max_j |exact_j| */
    double worst_ulp; /* max |l_i - exact_i| / ulp(exact_i) */
} stats;

static double ulp_of(double x)
{
    x = fabs(x);
    return nextafter(x, INFINITY) - x;
}

static int sgn(double x) { return (x > 0) - (x < 0); }

/*
 * Compare k coordinates l (status st) with the exact reference ref (status
 * rst). at_vertex: the query is a vertex, so the result must equal the
 * reference exactly.
 */
static void compare(stats *s, int k, geom_status st, const double *l, int rst, const double *ref,
                    int at_vertex)
{
    s->cases++;
    assert_true(rst == GV_OK || rst == GV_ERR_DEGENERATE);
    if (rst == GV_ERR_DEGENERATE) {
        s->degenerate++;
        assert_int_equal(st, GEOM_ERR_DEGENERATE);
        for (int i = 0; i < k; ++i)
            assert_true(l[i] == 0.0);
        return;
    }
    assert_int_equal(st, GEOM_OK);
    double m = 0;
    for (int i = 0; i < k; ++i)
        m = fmax(m, fabs(ref[i]));
    assert_true(m > 0 && isfinite(m)); /* the generators avoid overflowing coordinates */
    for (int i = 0; i < k; ++i) {
        if (ref[i] == 0.0) {
            s->zeros++;
            if (l[i] != 0.0)
                fail_msg("coordinate %d is %.17g, exact 0", i, l[i]);
            continue;
        }
        if (sgn(l[i]) != sgn(ref[i]))
            fail_msg("coordinate %d is %.17g, exact %.17g: wrong sign", i, l[i], ref[i]);
        const double err = fabs(l[i] - ref[i]);
        const double rel = err / m;
        if (!(rel <= 1e-9))
            fail_msg("coordinate %d is %.17g, exact %.17g: error %.3g of max |l| %.3g", i, l[i], ref[i],
                     err, m);
        s->worst_rel = fmax(s->worst_rel, rel);
        s->worst_ulp = fmax(s->worst_ulp, err / ulp_of(ref[i]));
    }
    if (at_vertex) {
        s->onvertex++;
        for (int i = 0; i < k; ++i)
            if (l[i] != ref[i])
                fail_msg("at a vertex: coordinate %d is %.17g, exact %.17g", i, l[i], ref[i]);
    }
}

static void report(const char *fn, const char *kind, const stats *s)
{
    printf("%-6s %-16s cases %6zu  degenerate %6zu  exact zeros %6zu  at vertex %6zu  "
           "worst err/max|l| %.3g  worst err %.3g ulp\n",
           fn, kind, s->cases, s->degenerate, s->zeros, s->onvertex, s->worst_rel, s->worst_ulp);
}

static void total(stats *t, const stats *s)
{
    t->cases += s->cases;
    t->degenerate += s->degenerate;
    t->zeros += s->zeros;
    t->onvertex += s->onvertex;
    t->worst_rel = fmax(t->worst_rel, s->worst_rel);
    t->worst_ulp = fmax(t->worst_ulp, s->worst_ulp);
}

/* --------------------------------------------------------- predicates */

static void check_orient2d(const double *a, const double *b, const double *c)
{
    const int ref = gv_orient2d(a, b, c);
    assert_true(ref >= -1 && ref <= 1);
    const int got = sgn(geom_orient2d(a, b, c));
    if (got != ref)
        fail_msg("orient2d((%a,%a),(%a,%a),(%a,%a)) sign %d, exact %d", a[0], a[1], b[0], b[1], c[0],
                 c[1], got, ref);
}

static void check_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    const int ref = gv_orient3d(a, b, c, d);
    assert_true(ref >= -1 && ref <= 1);
    const int got = sgn(geom_orient3d(a, b, c, d));
    if (got != ref)
        fail_msg("orient3d((%a,%a,%a),(%a,%a,%a),(%a,%a,%a),(%a,%a,%a)) sign %d, exact %d", a[0], a[1],
                 a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2], got, ref);
}

static void check_incircle(const double *a, const double *b, const double *c, const double *d)
{
    const int ref = gv_incircle(a, b, c, d);
    assert_true(ref >= -1 && ref <= 1);
    const int got = sgn(geom_incircle(a, b, c, d));
    if (got != ref)
        fail_msg("incircle((%a,%a),(%a,%a),(%a,%a),(%a,%a)) sign %d, exact %d", a[0], a[1], b[0], b[1],
                 c[0], c[1], d[0], d[1], got, ref);
}

/* ------------------------------------------------------ 2D generators */

enum kind2 {
    K2_RANDOM,
    K2_EDGE_DYADIC,
    K2_EDGE_AXIS,
    K2_VERTEX,
    K2_SLIVER,
    K2_OFFSET,
    K2_SLIVER_OFFSET,
    K2_TINY,
    K2_GRID,
    K2_COUNT
};
static const char *const kind2_name[K2_COUNT] = {"random", "on dyadic edge", "on axis edge",
                                                 "at vertex", "sliver", "offset 1e8",
                                                 "sliver+1e8", "tiny 1e-100", "ulp grid"};

/* A 2D case: triangle t[0..2], query p; at_vertex set when p is a vertex. */
typedef struct case2 {
    double t[3][2];
    double p[2];
    int at_vertex;
} case2;

static void random_tri2(rng *r, double t[3][2], double scale)
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 2; ++j)
            t[i][j] = scale * unif_in(r, -1, 1);
}

/* a sliver: c near the segment ab with area / |ab|^2 = ratio / 2 */
static void sliver2(rng *r, double t[3][2], double scale)
{
    for (int j = 0; j < 2; ++j) {
        t[0][j] = scale * unif_in(r, -1, 1);
        t[1][j] = scale * unif_in(r, -1, 1);
    }
    const double ratio = pow(10.0, -unif_in(r, 0, 15));
    const double s = unif(r);
    const double dx = t[1][0] - t[0][0], dy = t[1][1] - t[0][1];
    const double h = (next_u64(r) & 1 ? 1 : -1) * ratio;
    t[2][0] = t[0][0] + s * dx - h * dy;
    t[2][1] = t[0][1] + s * dy + h * dx;
}

static void query_near2(rng *r, double t[3][2], double p[2])
{
    /* an affine combination with weights in [-0.5, 1.5], rounded */
    const double u = unif_in(r, -0.5, 1.5), v = unif_in(r, -0.5, 1.5);
    for (int j = 0; j < 2; ++j)
        p[j] = t[0][j] + u * (t[1][j] - t[0][j]) + v * (t[2][j] - t[0][j]);
}

static void gen2(rng *r, int kind, case2 *c)
{
    memset(c, 0, sizeof *c);
    switch (kind) {
    case K2_RANDOM:
        random_tri2(r, c->t, 1);
        c->p[0] = unif_in(r, -2, 2);
        c->p[1] = unif_in(r, -2, 2);
        break;
    case K2_EDGE_DYADIC: {
        /* integer vertices, p = a + (j/1024)(b - a) exactly, on the line
         * through one edge (inside the segment or beyond it) */
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 2; ++j)
                c->t[i][j] = (double)int_in(r, -(1 << 20), 1 << 20);
        const int e = (int)int_in(r, 0, 2);
        const double *a = c->t[e], *b = c->t[(e + 1) % 3];
        const double s = (double)int_in(r, -512, 1536) / 1024.0;
        for (int j = 0; j < 2; ++j)
            c->p[j] = a[j] + s * (b[j] - a[j]);
        break;
    }
    case K2_EDGE_AXIS: {
        /* an edge along x or y at a random real height, p on its line */
        random_tri2(r, c->t, 1);
        const int e = (int)int_in(r, 0, 2), ax = (int)int_in(r, 0, 1);
        double *a = c->t[e], *b = c->t[(e + 1) % 3];
        b[1 - ax] = a[1 - ax];
        c->p[1 - ax] = a[1 - ax];
        c->p[ax] = unif_in(r, -1.5, 1.5);
        break;
    }
    case K2_VERTEX: {
        const int mode = (int)int_in(r, 0, 2);
        if (mode == 0)
            random_tri2(r, c->t, 1);
        else if (mode == 1)
            sliver2(r, c->t, 1);
        else {
            random_tri2(r, c->t, 1);
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 2; ++j)
                    c->t[i][j] += 1e8;
        }
        const int v = (int)int_in(r, 0, 2);
        c->p[0] = c->t[v][0];
        c->p[1] = c->t[v][1];
        c->at_vertex = 1;
        break;
    }
    case K2_SLIVER:
        sliver2(r, c->t, 1);
        query_near2(r, c->t, c->p);
        break;
    case K2_OFFSET:
    case K2_SLIVER_OFFSET:
        if (kind == K2_OFFSET)
            random_tri2(r, c->t, 1);
        else
            sliver2(r, c->t, 1);
        query_near2(r, c->t, c->p);
        for (int j = 0; j < 2; ++j) {
            const double off = 1e8 * (1 + unif(r));
            for (int i = 0; i < 3; ++i)
                c->t[i][j] += off;
            c->p[j] += off;
        }
        break;
    case K2_TINY:
        if (next_u64(r) & 1)
            random_tri2(r, c->t, 1e-100);
        else
            sliver2(r, c->t, 1e-100);
        query_near2(r, c->t, c->p);
        break;
    case K2_GRID: {
        /* Kettner et al.'s near-collinear grid: a, b on the diagonal and c,
         * p at (0.5 + i u, 0.5 + j u), u = ulp(0.5); i == j is exactly
         * collinear. A random rotation of roles moves the degenerate vertex. */
        const double u = 0x1p-53;
        double pts[4][2] = {{12, 12}, {24, 24}, {0, 0}, {0, 0}};
        for (int q = 2; q < 4; ++q) {
            pts[q][0] = 0.5 + (double)int_in(r, 0, 15) * u;
            pts[q][1] = 0.5 + (double)int_in(r, 0, 15) * u;
        }
        if (next_u64(r) & 1) { /* or the collinear midpoint moved by ulps */
            pts[2][0] = ulps(18, (int)int_in(r, -2, 2));
            pts[2][1] = ulps(18, (int)int_in(r, -2, 2));
        }
        const int rot = (int)int_in(r, 0, 2);
        for (int i = 0; i < 3; ++i)
            memcpy(c->t[(i + rot) % 3], pts[i], sizeof pts[i]);
        memcpy(c->p, pts[3], sizeof pts[3]);
        break;
    }
    default:
        fail();
    }
}

/* ------------------------------------------------------ 3D generators */

enum kind3 {
    K3_RANDOM,
    K3_EDGE_DYADIC,
    K3_AXIS,
    K3_VERTEX,
    K3_SLIVER,
    K3_OFFSET,
    K3_SLIVER_OFFSET,
    K3_TINY,
    K3_GRID,
    K3_COUNT
};
static const char *const kind3_name[K3_COUNT] = {"random", "on dyadic edge", "axis edge/face",
                                                 "at vertex", "sliver", "offset 1e8",
                                                 "sliver+1e8", "tiny 1e-100", "ulp grid"};

/* A 3D case: tetrahedron t[0..3] (triangle: t[0..2]), query p; at_vertex
 * set when p is one of t[0..2]. */
typedef struct case3 {
    double t[4][3];
    double p[3];
    int at_vertex;
} case3;

static void random_pts3(rng *r, double t[][3], int n, double scale)
{
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < 3; ++j)
            t[i][j] = scale * unif_in(r, -1, 1);
}

static void cross3(const double u[3], const double v[3], double w[3])
{
    w[0] = u[1] * v[2] - u[2] * v[1];
    w[1] = u[2] * v[0] - u[0] * v[2];
    w[2] = u[0] * v[1] - u[1] * v[0];
}

static double norm3(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* Sliver tetrahedron: t[0..2] a random triangle (itself a sliver half of
 * the time) and t[3] near its plane with volume / L^3 ~ ratio; the triangle
 * t[0..2] alone is a sliver triangle with area / L^2 ~ ratio when `tri`. */
static void sliver3(rng *r, double t[4][3], double scale, int tri)
{
    random_pts3(r, t, 2, scale);
    const double ratio = pow(10.0, -unif_in(r, 0, 15));
    double e[3], rnd[3], perp[3];
    for (int j = 0; j < 3; ++j) {
        e[j] = t[1][j] - t[0][j];
        rnd[j] = unif_in(r, -1, 1);
    }
    cross3(e, rnd, perp); /* perpendicular to e */
    const double L = norm3(e), pl = norm3(perp);
    const double s = unif(r);
    const double h = tri ? ratio : unif_in(r, 0.2, 1);
    for (int j = 0; j < 3; ++j)
        t[2][j] = t[0][j] + s * e[j] + h * L * perp[j] / pl;
    /* apex: a point of the plane plus ratio * L along the normal */
    double e2[3], n[3];
    for (int j = 0; j < 3; ++j)
        e2[j] = t[2][j] - t[0][j];
    cross3(e, e2, n);
    const double nl = norm3(n);
    const double u = unif(r), v = unif(r) * (1 - u);
    const double hh = tri ? unif_in(r, 0.2, 1) : ratio;
    for (int j = 0; j < 3; ++j)
        t[3][j] = t[0][j] + u * e[j] + v * e2[j] + (nl > 0 ? hh * L * n[j] / nl : 0);
}

static void query_near3(rng *r, double t[4][3], double p[3])
{
    const double u = unif_in(r, -0.5, 1.5), v = unif_in(r, -0.5, 1.5), w = unif_in(r, -0.5, 1.5);
    for (int j = 0; j < 3; ++j)
        p[j] = t[0][j] + u * (t[1][j] - t[0][j]) + v * (t[2][j] - t[0][j]) + w * (t[3][j] - t[0][j]);
}

static void gen3(rng *r, int kind, case3 *c)
{
    memset(c, 0, sizeof *c);
    switch (kind) {
    case K3_RANDOM:
        random_pts3(r, c->t, 4, 1);
        for (int j = 0; j < 3; ++j)
            c->p[j] = unif_in(r, -2, 2);
        break;
    case K3_EDGE_DYADIC: {
        /* integer vertices; p = a + (j/1024)(b - a) exactly on edge a-b,
         * where a = t[0], b = t[1], t[2] (edges of the triangle and the
         * tetrahedron), the triangle's third coordinate and two of the
         * tetrahedron's are exactly 0 */
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 3; ++j)
                c->t[i][j] = (double)int_in(r, -(1 << 20), 1 << 20);
        const int e = (int)int_in(r, 0, 2);
        const double *a = c->t[e], *b = c->t[(e + 1) % 3];
        const double s = (double)int_in(r, -512, 1536) / 1024.0;
        for (int j = 0; j < 3; ++j)
            c->p[j] = a[j] + s * (b[j] - a[j]);
        break;
    }
    case K3_AXIS: {
        /* triangle t[0..2] in the plane z = z0 with edge t[0]-t[1] along x;
         * p on that edge's line (then the triangle's coordinate 2 is exactly
         * 0) lifted off the plane by w: the projection stays on the line.
         * Half of the time p is instead exactly in the plane z = z0, on the
         * tetrahedron's face (t[0], t[1], t[2]): coordinate 3 is exactly 0. */
        random_pts3(r, c->t, 4, 1);
        const double z0 = c->t[0][2];
        c->t[1][2] = z0;
        c->t[2][2] = z0;
        c->t[1][1] = c->t[0][1];
        if (next_u64(r) & 1) {
            c->p[0] = unif_in(r, -1.5, 1.5);
            c->p[1] = c->t[0][1];
            c->p[2] = z0 + unif_in(r, -1, 1);
        } else {
            c->p[0] = unif_in(r, -1.5, 1.5);
            c->p[1] = unif_in(r, -1.5, 1.5);
            c->p[2] = z0;
        }
        break;
    }
    case K3_VERTEX: {
        const int mode = (int)int_in(r, 0, 2);
        if (mode == 0)
            random_pts3(r, c->t, 4, 1);
        else if (mode == 1)
            sliver3(r, c->t, 1, (int)(next_u64(r) & 1));
        else {
            random_pts3(r, c->t, 4, 1);
            for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 3; ++j)
                    c->t[i][j] += 1e8;
        }
        /* vertex 3 is not a vertex of the triangle: the triangle case uses
         * v < 3 only (see check_case3) */
        const int v = (int)int_in(r, 0, 2);
        memcpy(c->p, c->t[v], sizeof c->p);
        c->at_vertex = 1;
        break;
    }
    case K3_SLIVER:
        sliver3(r, c->t, 1, (int)(next_u64(r) & 1));
        query_near3(r, c->t, c->p);
        break;
    case K3_OFFSET:
    case K3_SLIVER_OFFSET:
        if (kind == K3_OFFSET)
            random_pts3(r, c->t, 4, 1);
        else
            sliver3(r, c->t, 1, (int)(next_u64(r) & 1));
        query_near3(r, c->t, c->p);
        for (int j = 0; j < 3; ++j) {
            const double off = 1e8 * (1 + unif(r));
            for (int i = 0; i < 4; ++i)
                c->t[i][j] += off;
            c->p[j] += off;
        }
        break;
    case K3_TINY:
        if (next_u64(r) & 1)
            random_pts3(r, c->t, 4, 1e-100);
        else
            sliver3(r, c->t, 1e-100, (int)(next_u64(r) & 1));
        query_near3(r, c->t, c->p);
        break;
    case K3_GRID: {
        /* Points of the plane z = x/2 + y/4 + 1/64 with x, y multiples of
         * 1/8 (exactly on it, and z is never 0, whose ulp is subnormal),
         * then z moved by a few ulps: exactly coplanar (degenerate)
         * tetrahedra and ones a few ulps thick. The triangle t[0..2] is
         * made near-collinear the same way along the line x = y = z. */
        for (int i = 0; i < 4; ++i) {
            const double x = (double)int_in(r, -64, 64) / 8, y = (double)int_in(r, -64, 64) / 8;
            c->t[i][0] = x;
            c->t[i][1] = y;
            c->t[i][2] = ulps(x / 2 + y / 4 + 1.0 / 64, (int)int_in(r, -1, 1) * (int)int_in(r, 0, 2));
        }
        if (next_u64(r) & 1) {
            /* a, b > 0: the midpoint is never 0, whose ulp is subnormal */
            const double a = (double)int_in(r, 1, 64) / 4, b = (double)int_in(r, 1, 64) / 4;
            const double m = (a + b) / 2;
            for (int j = 0; j < 3; ++j) {
                c->t[0][j] = a;
                c->t[1][j] = b;
                c->t[2][j] = ulps(m, (int)int_in(r, -1, 1) * (int)int_in(r, 0, 2));
            }
        }
        const double x = (double)int_in(r, -64, 64) / 8, y = (double)int_in(r, -64, 64) / 8;
        c->p[0] = x;
        c->p[1] = y;
        c->p[2] = ulps(x / 2 + y / 4 + 1.0 / 64, (int)int_in(r, -2, 2));
        break;
    }
    default:
        fail();
    }
}

/* ------------------------------------------------------------- tests */

static void test_shim_self_checks(void **state)
{
    (void)state;
    /* known exact answers */
    const double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1}, p[2] = {0.25, 0.5};
    double l[4];
    assert_int_equal(gv_bary_tri2(a, b, c, p, l), GV_OK);
    assert_true(l[0] == 0.25 && l[1] == 0.25 && l[2] == 0.5);
    assert_int_equal(gv_orient2d(a, b, c), 1);
    assert_int_equal(gv_orient2d(a, c, b), -1);
    assert_int_equal(gv_orient2d(a, b, (double[2]){3, 0}), 0);
    const double A[3] = {0, 0, 0}, B[3] = {1, 0, 0}, C[3] = {0, 1, 0}, D[3] = {0, 0, 1};
    /* d above counter-clockwise a, b, c: negative (geom_orient3d's convention) */
    assert_int_equal(gv_orient3d(A, B, C, D), -1);
    assert_int_equal(gv_orient3d(A, B, C, (double[3]){0, 0, -1}), 1);
    assert_int_equal(gv_orient3d(A, B, C, (double[3]){5, 7, 0}), 0);
    assert_int_equal(gv_incircle(a, b, c, (double[2]){0.5, 0.5}), 1);
    assert_int_equal(gv_incircle(a, b, c, (double[2]){1, 1}), 0);
    assert_int_equal(gv_incircle(a, b, c, (double[2]){2, 2}), -1);
    assert_int_equal(gv_incircle(a, c, b, (double[2]){0.5, 0.5}), -1);
    const double P3[3] = {0.25, 0.5, 3};
    assert_int_equal(gv_bary_tri3(A, B, C, P3, l), GV_OK);
    assert_true(l[0] == 0.25 && l[1] == 0.25 && l[2] == 0.5);
    const double Q[3] = {0.125, 0.25, 0.5};
    assert_int_equal(gv_bary_tet(A, B, C, D, Q, l), GV_OK);
    assert_true(l[0] == 0.125 && l[1] == 0.125 && l[2] == 0.25 && l[3] == 0.5);
    /* 1/3 rounded to nearest, not truncated */
    const double s[2] = {3, 0};
    assert_int_equal(gv_bary_tri2(a, s, (double[2]){0, 3}, (double[2]){1, 1}, l), GV_OK);
    assert_true(l[0] == 1.0 / 3 && l[1] == 1.0 / 3 && l[2] == 1.0 / 3);
    /* degenerate and invalid input */
    assert_int_equal(gv_bary_tri2(a, b, (double[2]){2, 0}, p, l), GV_ERR_DEGENERATE);
    assert_true(l[0] == 0 && l[1] == 0 && l[2] == 0);
    assert_int_equal(gv_bary_tri2(a, b, (double[2]){NAN, 0}, p, l), GV_ERR_INVALID);
    assert_int_equal(gv_orient2d(a, b, (double[2]){INFINITY, 0}), GV_SIGN_ERROR);
    assert_int_equal(gv_bary_tet(A, B, C, (double[3]){1, 1, 0}, Q, l), GV_ERR_DEGENERATE);

    /* The shim's rounding against IEEE division, which rounds num/den
     * correctly to nearest, normal and subnormal results alike. */
    rng r = {42};
    for (int i = 0; i < 20000; ++i) {
        double num = ldexp(unif_in(&r, -1, 1), (int)int_in(&r, -60, 60));
        const double den = ldexp(unif_in(&r, 0.5, 1), (int)int_in(&r, -60, 60));
        if (i % 4 == 0) /* results down in the subnormal range */
            num = ldexp(unif_in(&r, -1, 1), -1080 + (int)int_in(&r, 0, 80));
        double q;
        assert_int_equal(gv_div_rounded(num, den, &q), GV_OK);
        const double want = num / den;
        if (memcmp(&q, &want, sizeof q) != 0 && !(q == 0 && want == 0))
            fail_msg("gv_div_rounded(%a, %a) = %a, IEEE %a", num, den, q, want);
    }
}

static void test_orient2d_incircle(void **state)
{
    (void)state;
    rng r = {0x0123456789abcdefull};
    size_t n = 0;
    for (int kind = 0; kind < K2_COUNT; ++kind)
        for (int i = 0; i < N_PER_KIND; ++i) {
            case2 c;
            gen2(&r, kind, &c);
            check_orient2d(c.t[0], c.t[1], c.t[2]);
            check_orient2d(c.p, c.t[1], c.t[2]);
            check_orient2d(c.t[0], c.p, c.t[2]);
            check_orient2d(c.t[0], c.t[1], c.p);
            check_incircle(c.t[0], c.t[1], c.t[2], c.p);
            n += 4;
        }
    /* Near-cocircular: integer points of the circles of radius 5, 25 and
     * 65 (exactly cocircular), scaled by powers of 2 and shifted by
     * integers or 1e8-size dyadics (still exact), then moved by ulps. */
    static const int pyth[][2] = {{3, 4}, {5, 0}, {7, 24}, {15, 20}, {25, 0}, {16, 63}, {33, 56},
                                  {39, 52}, {25, 60}, {65, 0}};
    static const int radius[] = {5, 5, 25, 25, 25, 65, 65, 65, 65, 65};
    const int npy = (int)(sizeof pyth / sizeof pyth[0]);
    for (int i = 0; i < 3 * N_PER_KIND; ++i) {
        double q[4][2];
        const int rad = radius[int_in(&r, 0, npy - 1)];
        const double scale = ldexp(1.0, (int)int_in(&r, -30, 30));
        const double cx = (double)int_in(&r, -1000, 1000) + (i % 3 == 0 ? 1e8 : 0);
        const double cy = (double)int_in(&r, -1000, 1000);
        for (int k = 0; k < 4; ++k) {
            int idx;
            do
                idx = (int)int_in(&r, 0, npy - 1);
            while (radius[idx] != rad);
            const int sw = (int)int_in(&r, 0, 1);
            double x = pyth[idx][sw], y = pyth[idx][1 - sw];
            if (next_u64(&r) & 1)
                x = -x;
            if (next_u64(&r) & 1)
                y = -y;
            q[k][0] = (x + cx) * scale;
            q[k][1] = (y + cy) * scale;
        }
        const int which = (int)int_in(&r, 0, 3), ax = (int)int_in(&r, 0, 1);
        q[which][ax] = ulps(q[which][ax], (int)int_in(&r, -2, 2));
        check_incircle(q[0], q[1], q[2], q[3]);
        check_orient2d(q[0], q[1], q[2]);
        n++;
    }
    printf("orient2d/incircle: %zu orient2d and %d incircle cases agree with the exact signs\n", n,
           K2_COUNT * N_PER_KIND + 3 * N_PER_KIND);
}

static void test_orient3d(void **state)
{
    (void)state;
    rng r = {0x5eed0f0123ull};
    size_t n = 0;
    for (int kind = 0; kind < K3_COUNT; ++kind)
        for (int i = 0; i < N_PER_KIND; ++i) {
            case3 c;
            gen3(&r, kind, &c);
            check_orient3d(c.t[0], c.t[1], c.t[2], c.t[3]);
            check_orient3d(c.t[0], c.t[1], c.t[2], c.p);
            check_orient3d(c.p, c.t[1], c.t[2], c.t[3]);
            n += 3;
        }
    printf("orient3d: %zu cases agree with the exact signs\n", n);
}

static void test_bary_tri2(void **state)
{
    (void)state;
    rng r = {0xb0a7d00dull};
    stats all = {0};
    for (int kind = 0; kind < K2_COUNT; ++kind) {
        stats s = {0};
        for (int i = 0; i < N_PER_KIND; ++i) {
            case2 c;
            gen2(&r, kind, &c);
            double ref[3], l[3];
            const int rst = gv_bary_tri2(c.t[0], c.t[1], c.t[2], c.p, ref);
            const geom_status st = geom_bary_tri2(c.t[0], c.t[1], c.t[2], c.p, l);
            if (kind == K2_EDGE_DYADIC || kind == K2_EDGE_AXIS) /* the generator's promise */
                assert_true(rst != GV_OK || ref[0] == 0 || ref[1] == 0 || ref[2] == 0);
            compare(&s, 3, st, l, rst, ref, c.at_vertex);
        }
        report("tri2", kind2_name[kind], &s);
        total(&all, &s);
    }
    report("tri2", "ALL", &all);
    assert_true(all.cases >= 100000);
}

static void test_bary_tri3(void **state)
{
    (void)state;
    rng r = {0x7e57b3ull};
    stats all = {0};
    for (int kind = 0; kind < K3_COUNT; ++kind) {
        stats s = {0};
        for (int i = 0; i < N_PER_KIND; ++i) {
            case3 c;
            gen3(&r, kind, &c);
            double ref[3], l[3];
            const int rst = gv_bary_tri3(c.t[0], c.t[1], c.t[2], c.p, ref);
            const geom_status st = geom_bary_tri3(c.t[0], c.t[1], c.t[2], c.p, l);
            if (kind == K3_EDGE_DYADIC)
                assert_true(rst != GV_OK || ref[0] == 0 || ref[1] == 0 || ref[2] == 0);
            compare(&s, 3, st, l, rst, ref, c.at_vertex);
        }
        report("tri3", kind3_name[kind], &s);
        total(&all, &s);
    }
    report("tri3", "ALL", &all);
    assert_true(all.cases >= 100000);
}

static void test_bary_tet(void **state)
{
    (void)state;
    rng r = {0x7e7a1234ull};
    stats all = {0};
    for (int kind = 0; kind < K3_COUNT; ++kind) {
        stats s = {0};
        for (int i = 0; i < N_PER_KIND; ++i) {
            case3 c;
            gen3(&r, kind, &c);
            double ref[4], l[4];
            const int rst = gv_bary_tet(c.t[0], c.t[1], c.t[2], c.t[3], c.p, ref);
            const geom_status st = geom_bary_tet(c.t[0], c.t[1], c.t[2], c.t[3], c.p, l);
            if (kind == K3_EDGE_DYADIC)
                assert_true(rst != GV_OK || (ref[3] == 0 && (ref[0] == 0 || ref[1] == 0 || ref[2] == 0)));
            compare(&s, 4, st, l, rst, ref, c.at_vertex);
        }
        report("tet", kind3_name[kind], &s);
        total(&all, &s);
    }
    report("tet", "ALL", &all);
    assert_true(all.cases >= 100000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shim_self_checks), cmocka_unit_test(test_orient2d_incircle),
        cmocka_unit_test(test_orient3d),         cmocka_unit_test(test_bary_tri2),
        cmocka_unit_test(test_bary_tri3),        cmocka_unit_test(test_bary_tet),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
