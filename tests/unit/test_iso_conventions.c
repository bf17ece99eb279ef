/* The conventions marching squares (geom_implicit_contour) and marching
 * cubes (geom_iso_extract*) share: one field type, one grid description,
 * one inside convention (f <= iso inside, samples exactly on the isovalue
 * included), one saddle decision, one meaning of `refine`. The 2D contour
 * of a plane of samples is compared with the 3D surface's trace on that
 * plane, and both with brute force over the grid's edges. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/iso.h"

#define N 9  /* nodes per axis of the plane */
#define NZ 3 /* layers of the 3D grid; layer 0 is the plane compared */

static uint64_t rng_state;

static unsigned rnd(unsigned m)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (unsigned)((rng_state >> 33) % m);
}

/* Grid edge ids of the plane: x-edge (i, j)-(i+1, j) is 2 (i + N j),
 * y-edge (i, j)-(i, j+1) is 2 (i + N j) + 1. */
static long edge_of(double x, double y)
{
    int xi = x == floor(x), yi = y == floor(y);
    if (yi && !xi && x > 0 && x < N - 1)
        return 2 * ((long)floor(x) + N * (long)y);
    if (xi && !yi && y > 0 && y < N - 1)
        return 2 * ((long)x + N * (long)floor(y)) + 1;
    return -1; /* a node or outside */
}

static int is_node(double x, double y)
{
    return x == floor(x) && y == floor(y);
}

/* Brute force: crossing edges of the plane under "f <= iso inside". */
static int crossing(const double *v, long e, double iso)
{
    long n = e / 2;
    long i = n % N, j = n / N;
    double a = v[i + N * j], b = (e & 1) ? v[i + N * (j + 1)] : v[i + 1 + N * j];
    if ((e & 1) ? j + 1 >= N : i + 1 >= N)
        return 0;
    return (a <= iso) != (b <= iso);
}

typedef struct runs {
    geom_iso_surface s3;
    geom_implicit_isolines c2;
    double data[N * N * NZ];
    geom_implicit_grid g3, g2;
} runs;

/* The 3D surface of the grid and the 2D contour of its layer 0, both at
 * iso. The 2D field is the grid of layer 0 (one sample along z): its
 * values at the nodes are the samples exactly. */
static void extract_both(runs *r, double iso)
{
    memset(&r->g3, 0, sizeof r->g3);
    r->g3.dims[0] = r->g3.dims[1] = N;
    r->g3.dims[2] = NZ;
    r->g3.type = GEOM_IMPLICIT_SCALAR_F64;
    r->g3.data = r->data;
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.iso = iso;
    assert_int_equal(geom_iso_extract_grid(&r->g3, &o, &r->s3, NULL), GEOM_OK);

    r->g2 = r->g3;
    r->g2.dims[2] = 1;
    geom_implicit_field f;
    assert_int_equal(geom_iso_field_from_grid(&r->g2, &f), GEOM_OK);
    geom_implicit_contour_options co;
    memset(&co, 0, sizeof co);
    co.iso = iso;
    double b[4] = {0, 0, N - 1, N - 1};
    assert_int_equal(geom_implicit_contour(&f, b, N - 1, N - 1, &co, &r->c2, NULL), GEOM_OK);
}

static void free_both(runs *r)
{
    geom_iso_surface_free(&r->s3);
    geom_implicit_isolines_free(&r->c2);
}

/* ------------------------------------------------ samples on the isovalue */

static void test_same_crossing_edges_with_ties(void **state)
{
    (void)state;
    static runs r;
    size_t distinguishing = 0, ties = 0;
    for (int trial = 0; trial < 60; trial++) {
        rng_state = 1000u + (uint64_t)trial;
        double iso = trial % 3 == 0 ? 0.0 : trial % 3 == 1 ? 2.0 : -0.5;
        /* values iso - 1, iso, iso + 1 (exactly representable): a third
         * of the samples exactly on the isovalue */
        for (int q = 0; q < N * N * NZ; q++)
            r.data[q] = iso + ((double)rnd(3) - 1.0);
        extract_both(&r, iso);
        const double *v = r.data; /* layer 0 */

        /* brute force */
        unsigned char want[2 * N * N], got3[2 * N * N], got2[2 * N * N];
        memset(got3, 0, sizeof got3);
        memset(got2, 0, sizeof got2);
        size_t nwant = 0;
        for (long e = 0; e < 2 * N * N; e++) {
            want[e] = (unsigned char)crossing(v, e, iso);
            nwant += want[e];
            /* an edge from a sample on the isovalue to one below crosses
             * under "f < iso inside" but not under "f <= iso" */
            long n = e / 2, i = n % N, j = n / N;
            if ((e & 1) ? j + 1 < N : i + 1 < N) {
                double a = v[i + N * j], b = (e & 1) ? v[i + N * (j + 1)] : v[i + 1 + N * j];
                distinguishing += (a == iso && b < iso) || (b == iso && a < iso);
                ties += a == iso || b == iso;
            }
        }

        /* 3D: the vertices in the plane z = 0 are the crossings of the
         * plane's edges (those at a node moved along their edge), one each */
        size_t n3 = 0;
        for (size_t q = 0; q < r.s3.n_vertices; q++) {
            const double *p = r.s3.xyz + 3 * q;
            if (p[2] != 0.0)
                continue;
            long e = edge_of(p[0], p[1]);
            assert_true(e >= 0);
            assert_int_equal(got3[e], 0);
            got3[e] = 1;
            n3++;
        }
        assert_int_equal(n3, nwant);
        assert_memory_equal(got3, want, sizeof want);

        /* 2D: a vertex inside each crossing edge without a sample on the
         * isovalue, at the linear interpolation; one vertex at each node on
         * the isovalue that ends a crossing edge (it is inside: its
         * crossing edges go to nodes above iso) */
        unsigned char node_used[N * N];
        memset(node_used, 0, sizeof node_used);
        for (size_t q = 0; q < r.c2.n_vertices; q++) {
            double x = r.c2.xy[2 * q], y = r.c2.xy[2 * q + 1];
            if (is_node(x, y)) {
                int i = (int)x, j = (int)y;
                assert_true(v[i + N * j] == iso);
                assert_int_equal(node_used[i + N * j], 0);
                node_used[i + N * j] = 1;
                int any = 0;
                if (i + 1 < N) {
                    any |= v[i + 1 + N * j] > iso;
                    got2[2 * (i + N * j)] |= v[i + 1 + N * j] > iso;
                }
                if (i > 0) {
                    any |= v[i - 1 + N * j] > iso;
                    got2[2 * (i - 1 + N * j)] |= v[i - 1 + N * j] > iso;
                }
                if (j + 1 < N) {
                    any |= v[i + N * (j + 1)] > iso;
                    got2[2 * (i + N * j) + 1] |= v[i + N * (j + 1)] > iso;
                }
                if (j > 0) {
                    any |= v[i + N * (j - 1)] > iso;
                    got2[2 * (i + N * (j - 1)) + 1] |= v[i + N * (j - 1)] > iso;
                }
                assert_true(any);
            } else {
                long e = edge_of(x, y);
                assert_true(e >= 0);
                assert_true(want[e]);
                assert_int_equal(got2[e], 0);
                got2[e] = 1;
                /* values iso -+ 1 at the ends: the midpoint */
                assert_true((e & 1) ? y - floor(y) == 0.5 : x - floor(x) == 0.5);
            }
        }
        assert_memory_equal(got2, want, sizeof want);
        /* ... and the 2D and 3D vertices on a crossing edge agree (3D moves
         * a vertex at a node by at most 2^-20 of the edge along it) */
        for (size_t q = 0; q < r.s3.n_vertices; q++) {
            const double *p = r.s3.xyz + 3 * q;
            if (p[2] != 0.0)
                continue;
            double best = INFINITY;
            for (size_t w = 0; w < r.c2.n_vertices; w++)
                best = fmin(best, hypot(p[0] - r.c2.xy[2 * w], p[1] - r.c2.xy[2 * w + 1]));
            assert_true(best <= 1.0 / 1024);
        }
        free_both(&r);
    }
    /* the data can tell "f < iso" from "f <= iso" apart */
    assert_true(distinguishing > 100);
    assert_true(ties > 1000);
}

/* --------------------------------------------------- saddles, ties of D */

/* Sorted pair of edge ids. */
static int cmp_pair(const void *a, const void *b)
{
    const long *p = a, *q = b;
    return p[0] != q[0] ? (p[0] < q[0] ? -1 : 1) : p[1] != q[1] ? (p[1] < q[1] ? -1 : 1) : 0;
}

static void add_pair(long *pairs, size_t *n, long a, long b)
{
    pairs[2 * *n] = a < b ? a : b;
    pairs[2 * *n + 1] = a < b ? b : a;
    (*n)++;
}

/* Values in {-2, -1, 1, 2} (none on the isovalue): ambiguous cells whose
 * saddle value is exactly the isovalue (|d0 d2| = |d1 d3|) are frequent.
 * The 2D segments and the 3D surface's boundary edges on the face z = 0
 * join the same crossing edges: one asymptotic decider, ties included. */
static void test_same_saddle_decisions(void **state)
{
    (void)state;
    static runs r;
    static long p2[4 * 4 * N * N], p3[4 * 4 * N * N];
    size_t saddle_ties = 0, saddles = 0;
    static const double vals[4] = {-2, -1, 1, 2};
    for (int trial = 0; trial < 60; trial++) {
        rng_state = 5000u + (uint64_t)trial;
        for (int q = 0; q < N * N * NZ; q++)
            r.data[q] = vals[rnd(4)];
        extract_both(&r, 0.0);
        const double *v = r.data;
        for (int j = 0; j + 1 < N; j++)
            for (int i = 0; i + 1 < N; i++) {
                double d0 = v[i + N * j], d1 = v[i + 1 + N * j], d2 = v[i + 1 + N * (j + 1)],
                       d3 = v[i + N * (j + 1)];
                if ((d0 < 0) == (d2 < 0) && (d1 < 0) == (d3 < 0) && (d0 < 0) != (d1 < 0)) {
                    saddles++;
                    saddle_ties += d0 * d2 == d1 * d3;
                }
            }
        size_t n2 = 0, n3 = 0;
        for (size_t k = 0; k < r.c2.n_polylines; k++) {
            size_t a = r.c2.start[k], b = r.c2.start[k + 1];
            for (size_t q = a; q + 1 < b + (r.c2.closed[k] ? 1 : 0); q++) {
                uint32_t u = r.c2.indices[q], w = r.c2.indices[q + 1 < b ? q + 1 : a];
                long eu = edge_of(r.c2.xy[2 * u], r.c2.xy[2 * u + 1]);
                long ew = edge_of(r.c2.xy[2 * w], r.c2.xy[2 * w + 1]);
                assert_true(eu >= 0 && ew >= 0);
                add_pair(p2, &n2, eu, ew);
            }
        }
        /* boundary edges of the 3D mesh (used by one triangle) in z = 0 */
        const geom_iso_surface *s = &r.s3;
        for (size_t t = 0; t < s->n_triangles; t++)
            for (int k = 0; k < 3; k++) {
                uint32_t u = s->tris[3 * t + k], w = s->tris[3 * t + (k + 1) % 3];
                if (s->xyz[3 * u + 2] != 0.0 || s->xyz[3 * w + 2] != 0.0)
                    continue;
                int uses = 0;
                for (size_t t2 = 0; t2 < s->n_triangles; t2++)
                    for (int k2 = 0; k2 < 3; k2++) {
                        uint32_t a = s->tris[3 * t2 + k2], b = s->tris[3 * t2 + (k2 + 1) % 3];
                        uses += (a == u && b == w) || (a == w && b == u);
                    }
                if (uses != 1)
                    continue;
                add_pair(p3, &n3, edge_of(s->xyz[3 * u], s->xyz[3 * u + 1]),
                         edge_of(s->xyz[3 * w], s->xyz[3 * w + 1]));
            }
        assert_int_equal(n2, n3);
        qsort(p2, n2, 2 * sizeof(long), cmp_pair);
        qsort(p3, n3, 2 * sizeof(long), cmp_pair);
        assert_memory_equal(p2, p3, 2 * n2 * sizeof(long));
        free_both(&r);
    }
    assert_true(saddles > 200);
    assert_true(saddle_ties > 50);
}

/* A saddle value exactly on the isovalue joins the inside corners in 2D
 * and 3D alike. */
static void test_saddle_tie_joins_inside(void **state)
{
    (void)state;
    /* a single cell (two layers equal) with corners -1, 1, -1, 1 (d0..d3
     * counter-clockwise): the saddle value is exactly 0 */
    geom_implicit_grid g;
    memset(&g, 0, sizeof g);
    double d[8] = {-1, 1, 1, -1, -1, 1, 1, -1}; /* x fastest: (0,0) (1,0) (0,1) (1,1) */
    g.dims[0] = g.dims[1] = g.dims[2] = 2;
    g.type = GEOM_IMPLICIT_SCALAR_F64;
    g.data = d;
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract_grid(&g, NULL, &s, NULL), GEOM_OK);
    /* joined inside corners: one sheet (a tube's half would be two) */
    assert_int_equal(s.report.ambiguous_faces, 2);
    geom_implicit_grid g2 = g;
    g2.dims[2] = 1;
    geom_implicit_field f;
    assert_int_equal(geom_iso_field_from_grid(&g2, &f), GEOM_OK);
    geom_implicit_isolines c;
    double b[4] = {0, 0, 1, 1};
    assert_int_equal(geom_implicit_contour(&f, b, 1, 1, NULL, &c, NULL), GEOM_OK);
    assert_int_equal(c.report.saddles, 1);
    assert_int_equal(c.n_polylines, 2);
    /* inside corners (0,0) and (1,1) joined: the two segments cut off the
     * outside corners (1,0) and (0,1): each joins a bottom or top edge to
     * the right or left edge next to that corner */
    for (size_t k = 0; k < 2; k++) {
        const double *p = &c.xy[2 * c.indices[c.start[k]]];
        const double *q = &c.xy[2 * c.indices[c.start[k] + 1]];
        double cx = (p[0] == 1.0 || q[0] == 1.0) ? 1.0 : 0.0;
        double cy = (p[1] == 1.0 || q[1] == 1.0) ? 1.0 : 0.0;
        assert_true(cx != cy); /* the cut-off corner is (1,0) or (0,1) */
    }
    geom_implicit_isolines_free(&c);
    /* 3D: the face z = 0 joins the same corners: its trace cuts off the
     * outside corners (1,0) and (0,1) (two sheets around the outside
     * columns, each a quadrilateral of 2 triangles) */
    assert_int_equal(s.n_triangles, 4);
    size_t traced = 0;
    for (size_t t = 0; t < s.n_triangles; t++)
        for (int k = 0; k < 3; k++) {
            const double *p = s.xyz + 3 * s.tris[3 * t + k];
            const double *q = s.xyz + 3 * s.tris[3 * t + (k + 1) % 3];
            if (p[2] != 0.0 || q[2] != 0.0)
                continue;
            double cx = (p[0] == 1.0 || q[0] == 1.0) ? 1.0 : 0.0;
            double cy = (p[1] == 1.0 || q[1] == 1.0) ? 1.0 : 0.0;
            assert_true(cx != cy);
            traced++;
        }
    assert_int_equal(traced, 2);
    geom_iso_surface_free(&s);
}

/* ------------------------------------------------------------------ refine */

static double plane_value(void *u, const double p[3])
{
    (void)u;
    return p[0] * p[0] + p[1] - 0.3; /* curved along x: refinement moves vertices */
}

static void test_refine_one_meaning(void **state)
{
    (void)state;
    static const struct {
        int refine, exact, refined;
    } cases[] = {
        {GEOM_IMPLICIT_REFINE_AUTO, 1, 1},   {GEOM_IMPLICIT_REFINE_AUTO, 0, 0},
        {GEOM_IMPLICIT_REFINE_ALWAYS, 1, 1}, {GEOM_IMPLICIT_REFINE_ALWAYS, 0, 1},
        {GEOM_IMPLICIT_REFINE_NEVER, 1, 0},  {GEOM_IMPLICIT_REFINE_NEVER, 0, 0},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        geom_implicit_field f;
        memset(&f, 0, sizeof f);
        f.value = plane_value;
        f.exact = cases[k].exact;
        geom_implicit_contour_options co;
        memset(&co, 0, sizeof co);
        co.refine = cases[k].refine;
        geom_implicit_isolines c;
        double b2[4] = {-1, -1, 1, 1};
        assert_int_equal(geom_implicit_contour(&f, b2, 8, 8, &co, &c, NULL), GEOM_OK);
        geom_iso_options o;
        memset(&o, 0, sizeof o);
        o.refine = cases[k].refine;
        geom_iso_surface s;
        double b3[6] = {-1, -1, -1, 1, 1, 1};
        size_t res[3] = {8, 8, 2};
        assert_int_equal(geom_iso_extract(&f, b3, res, &o, &s, NULL), GEOM_OK);
        if (cases[k].refined) {
            assert_true(c.report.refined > 0);
            assert_true(s.report.refined > 0);
        } else {
            assert_int_equal(c.report.refined, 0);
            assert_int_equal(s.report.refined, 0);
        }
        geom_implicit_isolines_free(&c);
        geom_iso_surface_free(&s);
    }
    /* zero-initialised options: the same default (AUTO) in both */
    geom_implicit_contour_options co;
    memset(&co, 0, sizeof co);
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    assert_int_equal(co.refine, GEOM_IMPLICIT_REFINE_AUTO);
    assert_int_equal(o.refine, GEOM_IMPLICIT_REFINE_AUTO);
}

/* --------------------------------------------------- one type, old names */

static void test_one_field_one_grid(void **state)
{
    (void)state;
    /* the deprecated names are the same types */
    geom_implicit_field f;
    geom_iso_field *fi = &f;
    geom_implicit_grid g;
    geom_iso_grid *gi = &g;
    geom_implicit_volume_desc *gd = &g;
    (void)fi, (void)gi, (void)gd;
    assert_int_equal(GEOM_ISO_SCALAR_F32, GEOM_IMPLICIT_SCALAR_F32);
    assert_int_equal(GEOM_ISO_SCALAR_F64, GEOM_IMPLICIT_SCALAR_F64);

    /* one field from an expression feeds both contouring functions */
    geom_implicit_expr *e;
    const char *text = "sphere(0.7)";
    assert_int_equal(geom_implicit_expr_compile(text, strlen(text), NULL, &e, NULL), GEOM_OK);
    geom_implicit_field_from_expr(e, &f);
    assert_non_null(f.values);
    assert_non_null(f.gradients);
    assert_non_null(f.bounds);
    geom_implicit_field fo;
    assert_int_equal(geom_iso_field_from_expr(e, &fo), GEOM_OK);
    assert_memory_equal(&f, &fo, sizeof f);
    double p[3] = {0.1, 0.2, 0.3}, gr[3];
    double val = f.gradient(f.user, p, gr);
    assert_true(val == f.value(f.user, p));
    geom_implicit_isolines c;
    double b2[4] = {-1, -1, 1, 1};
    assert_int_equal(geom_implicit_contour(&f, b2, 16, 16, NULL, &c, NULL), GEOM_OK);
    assert_true(c.n_polylines == 1 && c.closed[0]);
    geom_implicit_isolines_free(&c);
    geom_iso_surface s;
    double b3[6] = {-1, -1, -1, 1, 1, 1};
    size_t res[3] = {12, 12, 12};
    assert_int_equal(geom_iso_extract(&f, b3, res, NULL, &s, NULL), GEOM_OK);
    assert_true(s.n_triangles > 0 && s.report.refined > 0); /* exact: refined by default */
    geom_iso_surface_free(&s);

    /* one grid: a volume's description is the grid marching cubes reads */
    geom_implicit_grid d;
    memset(&d, 0, sizeof d);
    d.dims[0] = d.dims[1] = d.dims[2] = 5;
    d.type = GEOM_IMPLICIT_SCALAR_F32;
    d.spacing[0] = d.spacing[1] = d.spacing[2] = 0.5;
    d.origin[0] = d.origin[1] = d.origin[2] = -1;
    geom_implicit_volume *vol;
    assert_int_equal(geom_implicit_volume_create(&d, NULL, &vol), GEOM_OK);
    float *fs = geom_implicit_volume_data(vol);
    for (int k = 0; k < 5; k++)
        for (int j = 0; j < 5; j++)
            for (int i = 0; i < 5; i++)
                fs[i + 5 * (j + 5 * k)] = (float)(0.25 * ((i - 2) * (i - 2) + (j - 2) * (j - 2) +
                                                          (k - 2) * (k - 2)) - 1.0);
    geom_implicit_grid vg, ig;
    geom_implicit_volume_get_desc(vol, &vg);
    assert_ptr_equal(vg.data, geom_implicit_volume_cdata(vol));
    assert_int_equal(geom_iso_grid_from_volume(vol, &ig), GEOM_OK);
    assert_memory_equal(&vg, &ig, sizeof vg);
    geom_iso_surface s1, s2;
    assert_int_equal(geom_iso_extract_grid(&vg, NULL, &s1, NULL), GEOM_OK);
    geom_implicit_field vf;
    geom_implicit_field_from_volume(vol, &vf);
    double vb[6] = {-1, -1, -1, 1, 1, 1};
    size_t vr[3] = {4, 4, 4};
    assert_int_equal(geom_iso_extract(&vf, vb, vr, NULL, &s2, NULL), GEOM_OK);
    assert_int_equal(s1.n_vertices, s2.n_vertices);
    assert_memory_equal(s1.xyz, s2.xyz, 3 * s1.n_vertices * sizeof(double));
    /* the interpolator reads the grid's own data when none is passed */
    double q[3] = {0.1, -0.3, 0.45};
    assert_true(geom_implicit_samples_value(&vg, NULL, q) == geom_implicit_volume_eval(vol, q));
    geom_iso_surface_free(&s1);
    geom_iso_surface_free(&s2);
    geom_implicit_volume_destroy(vol);
    geom_implicit_expr_destroy(e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_crossing_edges_with_ties),
        cmocka_unit_test(test_same_saddle_decisions),
        cmocka_unit_test(test_saddle_tie_joins_inside),
        cmocka_unit_test(test_refine_one_meaning),
        cmocka_unit_test(test_one_field_one_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
