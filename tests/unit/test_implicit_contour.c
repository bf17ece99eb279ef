/*
 * Tests of marching squares (geom_implicit_contour): convergence of a
 * circle's vertices (O(h^2) with linear interpolation, ~1e-16 with root
 * refinement), loop counts and orientation, the asymptotic decider against
 * the closed-form topology of the bilinear interpolant (its value at the
 * saddle point, checked itself by a flood fill of a fine sampling), values
 * exactly on the isovalue (no duplicate or zero-length segments, no holes),
 * NaN/Inf fields, mesh output and allocation failures.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/implicit.h"

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double urand(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static geom_implicit_expr *compile_ok(const char *s)
{
    geom_implicit_expr *e = NULL;
    geom_diag d;
    if (geom_implicit_expr_compile(s, strlen(s), NULL, &e, &d) != GEOM_OK)
        fail_msg("compile '%s': %s", s, d.message);
    return e;
}

/* Contour an expression; returns the compiled expression (to destroy). */
static geom_implicit_expr *contour_expr(const char *s, double x0, double y0, double x1, double y1,
                                        size_t nx, size_t ny, double iso, int refine,
                                        geom_implicit_isolines *out)
{
    geom_implicit_expr *e = compile_ok(s);
    geom_implicit_field f;
    geom_implicit_field_from_expr(e, &f);
    double b[4] = {x0, y0, x1, y1};
    geom_implicit_contour_options o;
    memset(&o, 0, sizeof o);
    o.iso = iso;
    o.refine = refine;
    geom_diag d;
    geom_status st = geom_implicit_contour(&f, b, nx, ny, &o, out, &d);
    if (st != GEOM_OK)
        fail_msg("contour '%s': %s", s, d.message);
    return e;
}

/* Structural checks every contour must pass: indices in range, no two
 * vertices at the same position, no zero-length segment, no segment twice
 * (either direction). Returns the number of segments. */
static size_t check_structure(const geom_implicit_isolines *c)
{
    for (size_t a = 0; a < c->n_vertices; a++) {
        assert_true(isfinite(c->xy[2 * a]) && isfinite(c->xy[2 * a + 1]));
        for (size_t b = a + 1; b < c->n_vertices; b++)
            if (c->xy[2 * a] == c->xy[2 * b] && c->xy[2 * a + 1] == c->xy[2 * b + 1])
                fail_msg("vertices %zu and %zu at the same position (%.17g, %.17g)", a, b,
                         c->xy[2 * a], c->xy[2 * a + 1]);
    }
    size_t nseg = 0;
    for (size_t k = 0; k < c->n_polylines; k++)
        nseg += c->start[k + 1] - c->start[k] - (c->closed[k] ? 0 : 1);
    uint32_t *seg = malloc(2 * (nseg + 1) * sizeof(uint32_t));
    assert_non_null(seg);
    size_t n = 0;
    for (size_t k = 0; k < c->n_polylines; k++) {
        size_t s = c->start[k], e = c->start[k + 1];
        assert_true(e > s);
        if (c->closed[k])
            assert_true(e - s >= 3);
        else
            assert_true(e - s >= 2);
        for (size_t q = s; q < e; q++) {
            assert_true(c->indices[q] < c->n_vertices);
            if (q + 1 < e || c->closed[k]) {
                uint32_t a = c->indices[q], b = c->indices[q + 1 < e ? q + 1 : s];
                assert_true(a != b);
                seg[2 * n] = a < b ? a : b;
                seg[2 * n + 1] = a < b ? b : a;
                n++;
            }
        }
    }
    assert_int_equal(n, nseg);
    for (size_t a = 0; a < n; a++)
        for (size_t b = a + 1; b < n; b++)
            if (seg[2 * a] == seg[2 * b] && seg[2 * a + 1] == seg[2 * b + 1])
                fail_msg("segment %u-%u appears twice", seg[2 * a], seg[2 * a + 1]);
    free(seg);
    return nseg;
}

static double signed_area(const geom_implicit_isolines *c, size_t k)
{
    double a = 0;
    size_t s = c->start[k], e = c->start[k + 1];
    for (size_t q = s; q < e; q++) {
        uint32_t i = c->indices[q], j = c->indices[q + 1 < e ? q + 1 : s];
        a += c->xy[2 * i] * c->xy[2 * j + 1] - c->xy[2 * j] * c->xy[2 * i + 1];
    }
    return 0.5 * a;
}

/* ------------------------------------------------------------- circles */

static double circle_error(size_t n, int refine, double *reported)
{
    const double cx = 0.13, cy = -0.07, r = 0.9;
    geom_implicit_isolines c;
    geom_implicit_expr *e = contour_expr("(x - 0.13)^2 + (y + 0.07)^2 - 0.81", -1.1, -1.1, 1.1,
                                         1.1, n, n, 0.0, refine, &c);
    check_structure(&c);
    assert_int_equal(c.n_polylines, 1);
    assert_true(c.closed[0]);
    assert_true(signed_area(&c, 0) > 0.0); /* counter-clockwise around the inside */
    double err = 0;
    for (size_t v = 0; v < c.n_vertices; v++) {
        double d = fabs(hypot(c.xy[2 * v] - cx, c.xy[2 * v + 1] - cy) - r);
        if (d > err)
            err = d;
    }
    *reported = c.report.error.max_error;
    assert_int_equal(c.report.error.method, GEOM_ERROR_SAMPLED);
    /* every node of the cells the sparse path samples (at least those
     * along the circle), plus the error measure */
    assert_true(c.report.error.evaluations >= c.n_vertices);
    assert_int_equal(c.report.cells, n * n);
    assert_true(c.report.seconds >= 0.0);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);
    return err;
}

static void test_circle_convergence(void **state)
{
    (void)state;
    double prev = 0, rep;
    for (size_t n = 16; n <= 256; n *= 2) {
        double err = circle_error(n, GEOM_IMPLICIT_REFINE_NEVER, &rep);
        /* the reported |f|/|grad f| estimates the distance to first order */
        assert_true(rep > 0.5 * err && rep < 2.0 * err);
        if (prev > 0) {
            double ratio = prev / err;
            if (!(ratio > 3.0 && ratio < 5.5))
                fail_msg("n=%zu: error %.3g, previous %.3g, ratio %.3f (want ~4)", n, err, prev,
                         ratio);
        }
        prev = err;
        double ref = circle_error(n, GEOM_IMPLICIT_REFINE_AUTO, &rep);
        if (!(ref < 1e-12 && rep < 1e-12))
            fail_msg("n=%zu refined: error %.3g, reported %.3g", n, ref, rep);
    }
}

static void test_two_circles(void **state)
{
    (void)state;
    geom_implicit_isolines c;
    geom_implicit_expr *e = contour_expr("union(sphere(-1, 0, 0, 0.6), sphere(1, 0.2, 0, 0.6))",
                                         -2, -1.5, 2, 1.5, 200, 150, 0.0, 0, &c);
    check_structure(&c);
    assert_int_equal(c.n_polylines, 2);
    for (size_t k = 0; k < 2; k++) {
        assert_true(c.closed[k]);
        double a = signed_area(&c, k);
        assert_true(fabs(a - 3.14159265358979 * 0.36) < 1e-3);
    }
    /* the same loops at iso = 0.2: radius 0.8 */
    geom_implicit_isolines c2;
    geom_implicit_expr *e2 = contour_expr("union(sphere(-1, 0, 0, 0.6), sphere(1, 0.2, 0, 0.6))",
                                          -2, -1.5, 2, 1.5, 200, 150, 0.2, 0, &c2);
    assert_int_equal(c2.n_polylines, 2);
    for (size_t v = 0; v < c2.n_vertices; v++) {
        double x = c2.xy[2 * v], y = c2.xy[2 * v + 1];
        double d = fmin(hypot(x + 1, y), hypot(x - 1, y - 0.2));
        assert_true(fabs(d - 0.8) < 1e-13);
    }
    /* at iso = 0.5 the circles (radius 1.1) overlap: one loop */
    geom_implicit_isolines c3;
    geom_implicit_expr *e3 = contour_expr("union(sphere(-1, 0, 0, 0.6), sphere(1, 0.2, 0, 0.6))",
                                          -2.5, -1.5, 2.5, 1.5, 100, 60, 0.5, 0, &c3);
    check_structure(&c3);
    assert_int_equal(c3.n_polylines, 1);
    assert_true(c3.closed[0]);
    geom_implicit_isolines_free(&c);
    geom_implicit_isolines_free(&c2);
    geom_implicit_isolines_free(&c3);
    geom_implicit_expr_destroy(e);
    geom_implicit_expr_destroy(e2);
    geom_implicit_expr_destroy(e3);
    /* an annulus: the outer loop counter-clockwise, the hole clockwise */
    geom_implicit_isolines c4;
    geom_implicit_expr *e4 =
        contour_expr("difference(sphere(1), sphere(0.5))", -1.3, -1.3, 1.3, 1.3, 64, 64, 0, 0, &c4);
    assert_int_equal(c4.n_polylines, 2);
    double a0 = signed_area(&c4, 0), a1 = signed_area(&c4, 1);
    assert_true((a0 > 0) != (a1 > 0));
    assert_true(fabs(fmax(a0, a1) - 3.14159265358979) < 1e-2);
    assert_true(fabs(fmin(a0, a1) + 3.14159265358979 * 0.25) < 1e-2);
    geom_implicit_isolines_free(&c4);
    geom_implicit_expr_destroy(e4);
}

/* -------------------------------------------------------------- saddles */

typedef struct bilinear {
    double d[4]; /* corner values at (0,0) (1,0) (1,1) (0,1) */
} bilinear;

static double bilinear_at(const bilinear *b, double s, double t)
{
    return b->d[0] * (1 - s) * (1 - t) + b->d[1] * s * (1 - t) + b->d[2] * s * t +
           b->d[3] * (1 - s) * t;
}

static double bilinear_cb(void *user, const double p[3])
{
    return bilinear_at(user, p[0], p[1]);
}

/* Reference 1: the interpolant's value at its saddle point. */
static double saddle_value(const bilinear *b)
{
    double den = b->d[0] + b->d[2] - b->d[1] - b->d[3];
    double s = (b->d[0] - b->d[3]) / den, t = (b->d[0] - b->d[1]) / den;
    return bilinear_at(b, s, t);
}

/* Reference 2: are corners ca and cb connected through {B < 0} on an
 * M x M sampling (4-connectivity)? */
static int flood_connected(const bilinear *b, int ca, int cb)
{
    enum { M = 201 };
    static unsigned char mark[M * M];
    static int stack[M * M];
    memset(mark, 0, sizeof mark);
    static const int cx[4] = {0, M - 1, M - 1, 0}, cy[4] = {0, 0, M - 1, M - 1};
    int sp = 0;
    stack[sp++] = cx[ca] + M * cy[ca];
    mark[stack[0]] = 1;
    while (sp) {
        int q = stack[--sp];
        int i = q % M, j = q / M;
        if (i == cx[cb] && j == cy[cb])
            return 1;
        static const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4; k++) {
            int a = i + di[k], c = j + dj[k];
            if (a < 0 || c < 0 || a >= M || c >= M || mark[a + M * c])
                continue;
            if (bilinear_at(b, a / (double)(M - 1), c / (double)(M - 1)) < 0) {
                mark[a + M * c] = 1;
                stack[sp++] = a + M * c;
            }
        }
    }
    return 0;
}

/* Does our one-cell contour join the inside corners? */
static int contour_joins(const bilinear *b, int code)
{
    geom_implicit_field f = {.value = bilinear_cb, .user = (void *)b, .exact = 1};
    double bounds[4] = {0, 0, 1, 1};
    geom_implicit_isolines c;
    assert_int_equal(geom_implicit_contour(&f, bounds, 1, 1, NULL, &c, NULL), GEOM_OK);
    assert_int_equal(c.report.saddles, 1);
    assert_int_equal(c.n_polylines, 2);
    int joined = -1;
    for (size_t k = 0; k < 2; k++) {
        assert_false(c.closed[k]);
        assert_int_equal(c.start[k + 1] - c.start[k], 2);
        const double *p = &c.xy[2 * c.indices[c.start[k]]];
        const double *q = &c.xy[2 * c.indices[c.start[k] + 1]];
        /* inside on the left: cross(q - p, centre-ish inside corner) */
        const double *bottom = p[1] == 0.0 ? p : q[1] == 0.0 ? q : NULL;
        const double *other = bottom == p ? q : p;
        if (bottom) {
            int right = other[0] == 1.0, left = other[0] == 0.0;
            assert_true(right || left);
            joined = code == 5 ? right : left;
        }
        /* crossings are exact (the field is linear along edges) */
        double mag = fmax(fmax(fabs(b->d[0]), fabs(b->d[1])), fmax(fabs(b->d[2]), fabs(b->d[3])));
        assert_true(fabs(bilinear_at(b, p[0], p[1])) <= 1e-15 * mag);
        assert_true(fabs(bilinear_at(b, q[0], q[1])) <= 1e-15 * mag);
        /* inside on the left of p -> q: the corner K between the two
         * crossed edges is cut off; it lies left of p -> q iff inside */
        double kx = (p[0] == 1.0 || q[0] == 1.0) ? 1.0 : 0.0;
        double ky = (p[1] == 1.0 || q[1] == 1.0) ? 1.0 : 0.0;
        double side = (q[0] - p[0]) * (ky - p[1]) - (q[1] - p[1]) * (kx - p[0]);
        assert_true(side != 0.0);
        assert_int_equal(side > 0.0, bilinear_at(b, kx, ky) < 0.0);
    }
    assert_true(joined >= 0);
    check_structure(&c);
    geom_implicit_isolines_free(&c);
    return joined;
}

static void test_asymptotic_decider(void **state)
{
    (void)state;
    int tested = 0, joined_count = 0;
    for (int trial = 0; tested < 400; trial++) {
        bilinear b;
        int code = trial % 2 ? 5 : 10;
        for (int k = 0; k < 4; k++) {
            double m = 0.05 + urand();
            int inside = code == 5 ? (k == 0 || k == 2) : (k == 1 || k == 3);
            b.d[k] = inside ? -m : m;
        }
        double sv = saddle_value(&b);
        double mx = fmax(fmax(fabs(b.d[0]), fabs(b.d[1])), fmax(fabs(b.d[2]), fabs(b.d[3])));
        if (fabs(sv) < 0.02 * mx)
            continue; /* too close to call by sampling */
        int ca = code == 5 ? 0 : 1, cb = code == 5 ? 2 : 3;
        int flood = flood_connected(&b, ca, cb);
        /* the two references agree */
        assert_int_equal(flood, sv < 0);
        int ours = contour_joins(&b, code);
        if (ours != flood)
            fail_msg("corners %g %g %g %g: saddle value %g, ours joins=%d", b.d[0], b.d[1],
                     b.d[2], b.d[3], sv, ours);
        joined_count += ours;
        tested++;
    }
    /* both outcomes were exercised */
    assert_true(joined_count > 50 && joined_count < 350);
    /* a saddle value of exactly 0 counts as inside (the library's one
     * convention, f <= iso, as the 3D face decider): the inside corners are
     * joined */
    bilinear t1 = {{1, -1, 1, -1}};
    assert_int_equal(contour_joins(&t1, 10), 1);
    bilinear t2 = {{-1, 1, -1, 1}};
    assert_int_equal(contour_joins(&t2, 5), 1);
    bilinear t3 = {{-3, 1, -1, 3}}; /* D = 3 - 3 = 0 */
    assert_int_equal(contour_joins(&t3, 5), 1);
    /* huge and tiny magnitudes: the determinant's sign survives scaling */
    bilinear t4 = {{-3e300, 1e300, -1.0000000000000002e300, 3e300}}; /* D > 0: joined */
    assert_int_equal(contour_joins(&t4, 5), 1);
    bilinear t5 = {{-3e-300, 1e-300, -1.0000000000000002e-300, 3e-300}};
    assert_int_equal(contour_joins(&t5, 5), 1);
}

/* --------------------------------------------- values equal to the iso */

static void test_iso_on_nodes(void **state)
{
    (void)state;
    geom_implicit_isolines c;
    /* a straight line through a column of nodes */
    geom_implicit_expr *e = contour_expr("x - 0.5", 0, 0, 1, 1, 4, 4, 0, 0, &c);
    check_structure(&c);
    assert_int_equal(c.n_polylines, 1);
    assert_false(c.closed[0]);
    assert_int_equal(c.n_vertices, 5);
    for (size_t q = c.start[0]; q < c.start[1]; q++) {
        uint32_t v = c.indices[q];
        assert_true(c.xy[2 * v] == 0.5);
        assert_true(c.xy[2 * v + 1] == (double)(q - c.start[0]) / 4.0); /* upwards */
    }
    assert_true(c.report.error.max_error == 0.0);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);

    /* a circle through 12 integer nodes: (+-3, +-4), (+-4, +-3), (+-5, 0), (0, +-5) */
    e = contour_expr("x^2 + y^2 - 25", -6, -6, 6, 6, 12, 12, 0, 0, &c);
    check_structure(&c);
    assert_int_equal(c.n_polylines, 1);
    assert_true(c.closed[0]);
    size_t on_nodes = 0;
    for (size_t v = 0; v < c.n_vertices; v++) {
        double x = c.xy[2 * v], y = c.xy[2 * v + 1];
        assert_true(fabs(hypot(x, y) - 5.0) < 1e-14);
        on_nodes += x == floor(x) && y == floor(y);
    }
    assert_int_equal(on_nodes, 12);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);

    /* x*y = 0: the inside quadrants II and IV are cut off along the axes
     * and, in the cells at the origin, by the chord between the zero nodes
     * next to it (the bilinear interpolant is zero on those cells' sides) */
    e = contour_expr("x*y", -2, -2, 2, 2, 4, 4, 0, 0, &c);
    size_t nseg = check_structure(&c);
    for (size_t v = 0; v < c.n_vertices; v++) {
        double x = c.xy[2 * v], y = c.xy[2 * v + 1];
        assert_true((x == 0.0) != (y == 0.0));
        assert_true(x == floor(x) && y == floor(y));
    }
    assert_int_equal(c.n_vertices, 8);
    assert_int_equal(nseg, 6);
    assert_int_equal(c.n_polylines, 2);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);

    /* a zero column (inside: f <= iso) with the outside on both sides: one
     * polyline, not two */
    e = contour_expr("(x - 0.5)^2", 0, 0, 1, 1, 4, 4, 0, 0, &c);
    nseg = check_structure(&c);
    assert_int_equal(nseg, 4);
    assert_int_equal(c.n_polylines, 1);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);
    /* ... and with the inside on both sides: nothing */
    e = contour_expr("-(x - 0.5)^2", 0, 0, 1, 1, 4, 4, 0, 0, &c);
    assert_int_equal(c.n_polylines, 0);
    assert_int_equal(c.n_vertices, 0);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);
    /* a constant field equal to the isovalue */
    e = contour_expr("2", 0, 0, 1, 1, 3, 3, 2.0, 0, &c);
    assert_int_equal(c.n_polylines, 0);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);
}

typedef struct grid_field {
    int n;
    const double *v; /* (n+1)^2 node values */
} grid_field;

/* Piecewise-bilinear interpolation of node values on [0, n]^2. */
static double grid_cb(void *user, const double p[3])
{
    const grid_field *g = user;
    int i = (int)floor(p[0]), j = (int)floor(p[1]);
    if (i < 0)
        i = 0;
    if (j < 0)
        j = 0;
    if (i >= g->n)
        i = g->n - 1;
    if (j >= g->n)
        j = g->n - 1;
    double s = p[0] - i, t = p[1] - j;
    int w = g->n + 1;
    bilinear b = {{g->v[i + w * j], g->v[i + 1 + w * j], g->v[i + 1 + w * (j + 1)],
                   g->v[i + w * (j + 1)]}};
    return bilinear_at(&b, s, t);
}

static void test_random_ternary_grids(void **state)
{
    (void)state;
    enum { N = 10 };
    double v[(N + 1) * (N + 1)];
    for (int trial = 0; trial < 300; trial++) {
        for (int k = 0; k < (N + 1) * (N + 1); k++)
            v[k] = floor(urand() * 3.0) - 1.0;
        grid_field g = {N, v};
        geom_implicit_field f = {.value = grid_cb, .user = &g, .exact = trial % 2};
        double bounds[4] = {0, 0, N, N};
        geom_implicit_isolines c;
        assert_int_equal(geom_implicit_contour(&f, bounds, N, N, NULL, &c, NULL), GEOM_OK);
        check_structure(&c);
        /* No holes: a vertex strictly inside an edge of the grid (not at a
         * node, not on the border) has exactly one segment in and one out. */
        size_t *deg_in = calloc(c.n_vertices + 1, sizeof(size_t));
        size_t *deg_out = calloc(c.n_vertices + 1, sizeof(size_t));
        for (size_t k = 0; k < c.n_polylines; k++) {
            size_t s = c.start[k], e = c.start[k + 1];
            for (size_t q = s; q < e; q++) {
                if (q + 1 == e && !c.closed[k])
                    break;
                deg_out[c.indices[q]]++;
                deg_in[c.indices[q + 1 < e ? q + 1 : s]]++;
            }
        }
        for (size_t a = 0; a < c.n_vertices; a++) {
            double x = c.xy[2 * a], y = c.xy[2 * a + 1];
            int node = x == floor(x) && y == floor(y);
            int border = x == 0 || y == 0 || x == N || y == N;
            /* every vertex lies on the isoline of the bilinear field */
            double pv[3] = {x, y, 0};
            assert_true(fabs(grid_cb(&g, pv)) < 1e-15);
            if (!node && !border && (deg_in[a] != 1 || deg_out[a] != 1))
                fail_msg("trial %d: vertex (%g, %g) has %zu in, %zu out", trial, x, y,
                         deg_in[a], deg_out[a]);
        }
        free(deg_in);
        free(deg_out);
        geom_implicit_isolines_free(&c);
    }
}

/* ---------------------------------------------------------- NaN and Inf */

static void test_nonfinite_fields(void **state)
{
    (void)state;
    geom_implicit_isolines c;
    /* NaN for x < 0 is outside (as +inf, as geom_iso_extract has it): the
     * inside strip 0 <= x <= 0.25 is closed on its NaN side too, the
     * vertices there refined onto the edge of the NaN region (x -> 0-) */
    geom_implicit_expr *e = contour_expr("sqrt(x) - 0.5", -1, 0, 1, 1, 8, 4, 0, 0, &c);
    check_structure(&c);
    assert_true(c.report.skipped_cells > 0);
    assert_int_equal(c.report.nan_nodes, 4 * 5);
    assert_int_equal(c.n_polylines, 2);
    size_t at_quarter = 0, at_nan_edge = 0;
    for (size_t v = 0; v < c.n_vertices; v++) {
        at_quarter += fabs(c.xy[2 * v] - 0.25) < 1e-16;
        at_nan_edge += c.xy[2 * v] <= 0.0 && c.xy[2 * v] > -1e-12;
    }
    assert_int_equal(at_quarter, 5);
    assert_int_equal(at_nan_edge, 5);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);
    /* +-inf at a node column: classified by sign, no NaN vertex */
    e = contour_expr("1/x - 2", -1, 0, 1, 1, 4, 2, 0, 0, &c);
    check_structure(&c);
    int found_half = 0;
    for (size_t v = 0; v < c.n_vertices; v++) {
        assert_true(isfinite(c.xy[2 * v]));
        found_half += fabs(c.xy[2 * v] - 0.5) < 1e-15;
    }
    assert_int_equal(found_half, 3);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);
    /* everything NaN */
    e = contour_expr("sqrt(-1 - x*x)", -1, -1, 1, 1, 5, 5, 0, 0, &c);
    assert_int_equal(c.n_polylines, 0); /* all outside */
    assert_int_equal(c.report.skipped_cells, 25);
    assert_int_equal(c.report.nan_nodes, 36);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);
}

/* ------------------------------------------- NaN is +inf, as in 3D */

/* A 2D grid field (user = values, nx1 per row, cell size 1). */
typedef struct gridf {
    const double *v;
    size_t nx1, ny1;
} gridf;

static double grid_value(void *user, const double p[3])
{
    const gridf *g = user;
    long i = lround(p[0]), j = lround(p[1]);
    if (i < 0 || j < 0 || (size_t)i >= g->nx1 || (size_t)j >= g->ny1)
        return 1.0;
    if (fabs(p[0] - (double)i) > 1e-9 || fabs(p[1] - (double)j) > 1e-9) {
        /* between nodes (refinement off: never asked) */
        return NAN;
    }
    return g->v[(size_t)i + g->nx1 * (size_t)j];
}

static void contour_grid(const double *v, size_t n1, geom_implicit_isolines *c)
{
    gridf g = {v, n1, n1};
    geom_implicit_field f;
    memset(&f, 0, sizeof f);
    f.value = grid_value;
    f.user = &g;
    double b[4] = {0, 0, (double)(n1 - 1), (double)(n1 - 1)};
    geom_implicit_contour_options o;
    memset(&o, 0, sizeof o);
    o.refine = GEOM_IMPLICIT_REFINE_NEVER;
    assert_int_equal(geom_implicit_contour(&f, b, n1 - 1, n1 - 1, &o, c, NULL), GEOM_OK);
}

/* A grid with NaN nodes contours exactly as the same grid with +inf there
 * (the 3D convention: geom_iso_extract's NaN is +ISO_BIG, outside), on
 * random ternary grids with NaN sprinkled in; the NaN report stays. The old
 * code made no segment in a cell with a NaN corner. */
static void test_nan_is_outside_as_in_3d(void **state)
{
    (void)state;
    enum { N1 = 9 };
    double a[N1 * N1], b[N1 * N1];
    size_t differing_cells = 0;
    for (int trial = 0; trial < 200; trial++) {
        for (size_t k = 0; k < N1 * N1; k++) {
            double r = urand();
            a[k] = r < 0.15 ? NAN : r < 0.5 ? -1.0 : r < 0.6 ? 0.0 : 2.0 * urand() + 0.1;
            b[k] = isnan(a[k]) ? INFINITY : a[k];
        }
        geom_implicit_isolines ca, cb;
        contour_grid(a, N1, &ca);
        contour_grid(b, N1, &cb);
        check_structure(&ca);
        assert_int_equal(ca.n_vertices, cb.n_vertices);
        assert_int_equal(ca.n_polylines, cb.n_polylines);
        assert_memory_equal(ca.xy, cb.xy, 2 * ca.n_vertices * sizeof(double));
        assert_memory_equal(ca.start, cb.start, (ca.n_polylines + 1) * sizeof(size_t));
        if (ca.n_polylines) {
            assert_memory_equal(ca.indices, cb.indices, ca.start[ca.n_polylines] * sizeof(uint32_t));
            assert_memory_equal(ca.closed, cb.closed, ca.n_polylines);
        }
        assert_int_equal(ca.report.saddles, cb.report.saddles);
        assert_true(ca.report.nan_nodes > 0);
        assert_int_equal(cb.report.nan_nodes, 0);
        /* the first NaN in scan order */
        size_t first = SIZE_MAX;
        for (size_t k = 0; k < N1 * N1 && first == SIZE_MAX; k++)
            if (isnan(a[k]))
                first = k;
        assert_int_equal(ca.report.nan_first[0], first % N1);
        assert_int_equal(ca.report.nan_first[1], first / N1);
        differing_cells += ca.report.skipped_cells;
        geom_implicit_isolines_free(&ca);
        geom_implicit_isolines_free(&cb);
    }
    assert_true(differing_cells > 1000);
    /* one NaN corner next to three inside ones: a segment cuts it off (the
     * old code made none) */
    double g[4] = {-1, NAN, -1, -1};
    geom_implicit_isolines c;
    contour_grid(g, 2, &c);
    assert_int_equal(c.n_polylines, 1);
    assert_int_equal(c.n_vertices, 2);
    geom_implicit_isolines_free(&c);
}

/* ------------------------------------------------ sparse = dense */

static void contour_field(const geom_implicit_field *f, const double b[4], size_t nx, size_t ny,
                          double iso, int refine, geom_implicit_isolines *c)
{
    geom_implicit_contour_options o;
    memset(&o, 0, sizeof o);
    o.iso = iso;
    o.refine = refine;
    geom_diag d;
    if (geom_implicit_contour(f, b, nx, ny, &o, c, &d) != GEOM_OK)
        fail_msg("contour: %s", d.message);
}

/* With field->bounds (the sparse path: blocks the interval bounds prove
 * free of the isoline are skipped) the output equals the dense path's
 * (the same field without bounds) vertex for vertex, bit for bit and in the
 * same order, with the same report but for the evaluations; and the work
 * is a small part of the grid for a curve. */
static void test_sparse_equals_dense(void **state)
{
    (void)state;
    static const struct {
        const char *e;
        double b[4];
        size_t nx, ny;
        double iso;
    } cases[] = {
        {"x^2 + y^2 - 1", {-2, -2, 2, 2}, 300, 300, 0},
        {"x^2 + y^2 - 1", {-2, -2, 2, 2}, 77, 301, 0.5},
        {"sin(3*x) * sin(3*y)", {-3, -3, 3, 3}, 250, 250, 0},     /* saddles, lines */
        {"sin(x) * sin(y)", {-6.2831853071795862, -6.2831853071795862, 6.2831853071795862,
                             6.2831853071795862}, 64, 64, 0},     /* zeros on nodes */
        {"sqrt(sin(7*x)) - 0.5", {-1, -1, 1, 1}, 200, 90, 0},     /* NaN patches */
        {"torus(1, 0.3)", {-2, -2, 2, 2}, 333, 200, 0},
        {"gyroid(2)", {-3, -3, 3, 3}, 180, 180, 0.2},
        {"max(abs(x), abs(y)) - 1", {-1.5, -1.5, 1.5, 1.5}, 30, 30, 0}, /* on nodes */
        {"x", {-1, -1, 1, 1}, 1, 1, 0},
        {"1/x - 2", {-1, 0, 1, 1}, 40, 20, 0},                     /* infinities */
        {"(x - 1e8)^2 + y^2 - 1", {1e8 - 2, -2, 1e8 + 2, 2}, 500, 500, 0},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++)
        for (int refine = GEOM_IMPLICIT_REFINE_NEVER; refine >= GEOM_IMPLICIT_REFINE_AUTO;
             refine--) {
            geom_implicit_expr *e = compile_ok(cases[k].e);
            geom_implicit_field sparse, dense;
            geom_implicit_field_from_expr(e, &sparse);
            dense = sparse;
            dense.bounds = NULL;
            geom_implicit_isolines a, b;
            contour_field(&sparse, cases[k].b, cases[k].nx, cases[k].ny, cases[k].iso, refine, &a);
            contour_field(&dense, cases[k].b, cases[k].nx, cases[k].ny, cases[k].iso, refine, &b);
            if (a.n_vertices != b.n_vertices || a.n_polylines != b.n_polylines)
                fail_msg("'%s': sparse %zu vertices %zu polylines, dense %zu, %zu", cases[k].e,
                         a.n_vertices, a.n_polylines, b.n_vertices, b.n_polylines);
            assert_memory_equal(a.xy, b.xy, 2 * a.n_vertices * sizeof(double));
            assert_memory_equal(a.start, b.start, (a.n_polylines + 1) * sizeof(size_t));
            if (a.n_polylines) {
                assert_memory_equal(a.indices, b.indices,
                                    a.start[a.n_polylines] * sizeof(uint32_t));
                assert_memory_equal(a.closed, b.closed, a.n_polylines);
            }
            assert_int_equal(a.report.cells, b.report.cells);
            assert_int_equal(a.report.saddles, b.report.saddles);
            assert_int_equal(a.report.skipped_cells, b.report.skipped_cells);
            assert_int_equal(a.report.nan_nodes, b.report.nan_nodes);
            assert_int_equal(a.report.nan_first[0], b.report.nan_first[0]);
            assert_int_equal(a.report.nan_first[1], b.report.nan_first[1]);
            assert_int_equal(a.report.refined, b.report.refined);
            assert_true(a.report.error.max_error == b.report.error.max_error);
            assert_true(a.report.error.evaluations <= b.report.error.evaluations);
            /* the estimate of the work: exact for the dense path */
            double cells_sparse = -1, cells_dense = -1;
            geom_implicit_contour_options o;
            memset(&o, 0, sizeof o);
            o.iso = cases[k].iso;
            assert_int_equal(geom_implicit_contour_estimate_cells(&sparse, cases[k].b, cases[k].nx,
                                                                  cases[k].ny, &o, &cells_sparse),
                             GEOM_OK);
            assert_int_equal(geom_implicit_contour_estimate_cells(&dense, cases[k].b, cases[k].nx,
                                                                  cases[k].ny, &o, &cells_dense),
                             GEOM_OK);
            assert_true(cells_dense == (double)cases[k].nx * (double)cases[k].ny);
            assert_true(cells_sparse <= cells_dense);
            geom_implicit_isolines_free(&a);
            geom_implicit_isolines_free(&b);
            geom_implicit_expr_destroy(e);
        }
}

/* The time scales with the curve, not the grid: a circle on a 20000^2 grid
 * (4e8 cells; the dense path took about 90 s) samples under 1% of the
 * cells, and the work estimate says so before the work. */
static void test_sparse_work(void **state)
{
    (void)state;
    const size_t n = 20000;
    geom_implicit_expr *e = compile_ok("x^2 + y^2 - 1");
    geom_implicit_field f;
    geom_implicit_field_from_expr(e, &f);
    double b[4] = {-2, -2, 2, 2};
    double cells = 0;
    assert_int_equal(geom_implicit_contour_estimate_cells(&f, b, n, n, NULL, &cells), GEOM_OK);
    assert_true(cells > 0 && cells < 0.01 * (double)n * (double)n);
    geom_implicit_isolines c;
    contour_field(&f, b, n, n, 0, GEOM_IMPLICIT_REFINE_NEVER, &c);
    assert_int_equal(c.n_polylines, 1);
    assert_true(c.n_vertices > 19 * n / 10); /* about 8 / h = 2 n crossings */
    assert_true((double)c.report.error.evaluations < 4.0 * cells + 4.0 * (double)c.n_vertices);
    assert_int_equal(c.report.cells, n * n);
    geom_implicit_isolines_free(&c);
    /* bad arguments */
    assert_int_equal(geom_implicit_contour_estimate_cells(&f, b, n, n, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_implicit_contour_estimate_cells(NULL, b, n, n, NULL, &cells),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_implicit_contour_estimate_cells(&f, b, 0, n, NULL, &cells),
                     GEOM_ERR_INVALID_ARG);
    double empty[4] = {0, 0, 0, 1};
    assert_int_equal(geom_implicit_contour_estimate_cells(&f, empty, n, n, NULL, &cells),
                     GEOM_ERR_INVALID_ARG);
    geom_implicit_expr_destroy(e);
}

static void test_invalid_arguments(void **state)
{
    (void)state;
    geom_implicit_expr *e = compile_ok("x");
    geom_implicit_field f;
    geom_implicit_field_from_expr(e, &f);
    geom_implicit_isolines c;
    double good[4] = {0, 0, 1, 1}, empty[4] = {0, 0, 0, 1}, inf[4] = {0, 0, INFINITY, 1};
    geom_diag d;
    assert_int_equal(geom_implicit_contour(NULL, good, 2, 2, NULL, &c, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_implicit_contour(&f, NULL, 2, 2, NULL, &c, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_implicit_contour(&f, good, 2, 2, NULL, NULL, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_implicit_contour(&f, empty, 2, 2, NULL, &c, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "empty bounds"));
    assert_int_equal(geom_implicit_contour(&f, inf, 2, 2, NULL, &c, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_implicit_contour(&f, good, 0, 2, NULL, &c, NULL), GEOM_ERR_INVALID_ARG);
    geom_implicit_contour_options o;
    memset(&o, 0, sizeof o);
    o.iso = NAN;
    assert_int_equal(geom_implicit_contour(&f, good, 2, 2, &o, &c, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_implicit_contour(&f, good, SIZE_MAX / 2, 2, NULL, &c, NULL),
                     GEOM_ERR_LIMIT);
    geom_implicit_isolines_free(&c);
    geom_implicit_isolines_free(NULL);
    geom_implicit_expr_destroy(e);
}

/* ------------------------------------------------------------ mesh out */

static void test_to_mesh(void **state)
{
    (void)state;
    geom_implicit_isolines c;
    geom_implicit_expr *e = contour_expr("union(sphere(-1, 0, 0, 0.5), 1.5 - x)", -2, -1, 2, 1,
                                         40, 20, 0, 0, &c);
    check_structure(&c);
    assert_int_equal(c.n_polylines, 2);
    geom_mesh *m = geom_mesh_create(NULL);
    double p[3] = {9, 9, 9};
    assert_int_equal(geom_mesh_add_vertex(m, p, NULL), GEOM_OK);
    assert_int_equal(geom_implicit_isolines_to_mesh(&c, 0.25, m), GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m), c.n_vertices + 1);
    assert_int_equal(geom_mesh_polyline_count(m), 2);
    const double *pos = geom_mesh_positions(m);
    for (size_t k = 0; k < 2; k++) {
        size_t n;
        const uint32_t *vs;
        assert_int_equal(geom_mesh_polyline_get(m, k, &n, &vs), GEOM_OK);
        size_t len = c.start[k + 1] - c.start[k];
        assert_int_equal(n, len + (c.closed[k] ? 1 : 0));
        if (c.closed[k])
            assert_int_equal(vs[0], vs[n - 1]);
        for (size_t q = 0; q < len; q++) {
            assert_int_equal(vs[q], c.indices[c.start[k] + q] + 1);
            assert_true(pos[3 * vs[q] + 2] == 0.25);
            assert_true(pos[3 * vs[q]] == c.xy[2 * c.indices[c.start[k] + q]]);
        }
    }
    geom_mesh_destroy(m);
    geom_implicit_isolines_free(&c);
    geom_implicit_expr_destroy(e);
}

/* ----------------------------------------------------------- allocator */

typedef struct counting {
    size_t live, calls, fail_at;
} counting;

static void *c_alloc(void *user, size_t size)
{
    counting *c = user;
    if (++c->calls == c->fail_at)
        return NULL;
    c->live += size;
    return malloc(size);
}
static void *c_realloc(void *user, void *ptr, size_t old, size_t size)
{
    counting *c = user;
    if (++c->calls == c->fail_at)
        return NULL;
    c->live += size;
    c->live -= old;
    return realloc(ptr, size);
}
static void c_free(void *user, void *ptr, size_t size)
{
    counting *c = user;
    if (ptr)
        c->live -= size;
    free(ptr);
}

static void test_allocation_failures(void **state)
{
    (void)state;
    geom_implicit_expr *e = compile_ok("min(gyroid(3), sphere(2))");
    geom_implicit_field f;
    geom_implicit_field_from_expr(e, &f);
    double b[4] = {-2.5, -2.5, 2.5, 2.5};
    size_t ok = 0;
    for (size_t fail = 1; fail < 80; fail++) {
        counting cnt = {0, 0, fail};
        geom_allocator a = {c_alloc, c_realloc, c_free, &cnt};
        geom_implicit_contour_options o;
        memset(&o, 0, sizeof o);
        o.alloc = &a;
        geom_implicit_isolines c;
        geom_status st = geom_implicit_contour(&f, b, 60, 60, &o, &c, NULL);
        if (st == GEOM_OK) {
            ok++;
            check_structure(&c);
            geom_implicit_isolines_free(&c);
        } else {
            assert_int_equal(st, GEOM_ERR_NOMEM);
            assert_int_equal(c.n_vertices, 0);
            assert_null(c.xy);
        }
        if (cnt.live != 0)
            fail_msg("failing allocation %zu (status %d): %zu bytes leaked", fail, st, cnt.live);
    }
    assert_true(ok > 0 && ok < 79);
    geom_implicit_expr_destroy(e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_circle_convergence),
        cmocka_unit_test(test_two_circles),
        cmocka_unit_test(test_asymptotic_decider),
        cmocka_unit_test(test_iso_on_nodes),
        cmocka_unit_test(test_random_ternary_grids),
        cmocka_unit_test(test_nonfinite_fields),
        cmocka_unit_test(test_nan_is_outside_as_in_3d),
        cmocka_unit_test(test_sparse_equals_dense),
        cmocka_unit_test(test_sparse_work),
        cmocka_unit_test(test_invalid_arguments),
        cmocka_unit_test(test_to_mesh),
        cmocka_unit_test(test_allocation_failures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
