/* Surface module: adaptive tessellation never needs more triangles than a
 * uniform grid (issue 14). For the NURBS sphere and torus at tolerances
 * 1e-2, 3e-3 and 1e-3, and Newell's teapot at 1e-2 and 3e-3: the adaptive result (A triangles, error within the tolerance)
 * against every uniform gu x gv grid per knot span (geom_surface_tessellate
 * in uniform mode, the same sampled error measure) with fewer than A
 * triangles: none may reach the tolerance. The search is brute force over a
 * box of (gu, gv), made here, not read from saved numbers (the tessellator
 * now searches these grids itself and returns one that has fewer
 * triangles, test_uniform_chosen; this search is the independent check);
 * the box's sides
 * come from two facts: a grid's triangle count grows with gu and with gv
 * (counted by a uniform run with no error samples), and its error does not
 * grow when gu or gv grows (used only to bound the box: gv below v_lb fails
 * at gu = G, so at every gu <= G; gu > G with fewer than A triangles forces
 * gv small enough that the grid fails at the largest such gu). Inside the
 * box every grid is run. The adaptive result is also crack-free and
 * deterministic (two runs, same triangles). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bench/tess_shapes.h"
#include "geom/surface.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct shape {
    const char *name;
    const geom_nurbs_surface *s;
    size_t n;
} shape;

/* One run: triangles, reported error and (if asked) boundary edges. */
static size_t run(const shape *sh, const geom_surface_tess_options *o, double *err,
                  size_t *open_edges)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    geom_error_report rep;
    geom_surface_tess_stats st;
    geom_diag d;
    geom_diag_clear(&d);
    geom_status rc = geom_surface_tessellate(sh->s, sh->n, o, m, &rep, &st, &d);
    if (rc != GEOM_OK)
        fail_msg("%s: %s (%s)", sh->name, geom_status_str(rc), d.message);
    if (err)
        *err = rep.max_error;
    if (open_edges)
        *open_edges = st.boundary_edges;
    geom_mesh_destroy(m);
    return st.triangles;
}

/* Uniform gu x gv per span: the triangle count (cheap: no error samples
 * with check_subdivisions 1) or, with err, the count and the error. */
static size_t uniform(const shape *sh, size_t gu, size_t gv, double *err)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.mode = GEOM_SURFACE_TESS_UNIFORM;
    o.grid_u = (int)gu;
    o.grid_v = (int)gv;
    o.check_subdivisions = err ? 0 : 1;
    return run(sh, &o, err, NULL);
}

static int uniform_passes(const shape *sh, size_t gu, size_t gv, double tol)
{
    double e;
    uniform(sh, gu, gv, &e);
    return e <= tol;
}

/* Largest g (0 if none) with count(g, other) < A, the varying count along
 * dir 0 (u) or 1 (v). */
static size_t largest_under(const shape *sh, int dir, size_t other, size_t A)
{
#define COUNT(g) (dir == 0 ? uniform(sh, (g), other, NULL) : uniform(sh, other, (g), NULL))
    if (COUNT(1) >= A)
        return 0;
    size_t lo = 1, hi = 2;
    while (COUNT(hi) < A)
        lo = hi, hi *= 2;
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (COUNT(mid) < A)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
#undef COUNT
}

/* Smallest g with the grid passing at (G, g) (dir 1) or (g, G) (dir 0),
 * g up to cap (cap + 1: none). */
static size_t smallest_passing(const shape *sh, int dir, size_t G, size_t cap, double tol)
{
    for (size_t g = 1; g <= cap; ++g)
        if (dir == 0 ? uniform_passes(sh, g, G, tol) : uniform_passes(sh, G, g, tol))
            return g;
    return cap + 1;
}

static void check_shape(const shape *sh, double tol)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = tol;
    double ea, eb;
    size_t open_a, open_b;
    size_t A = run(sh, &o, &ea, &open_a);
    /* deterministic, and as closed as the shape's uniform grid */
    assert_int_equal(run(sh, &o, &eb, &open_b), A);
    assert_true(ea == eb && open_a == open_b);
    size_t open_u;
    geom_surface_tess_options u;
    memset(&u, 0, sizeof u);
    u.mode = GEOM_SURFACE_TESS_UNIFORM;
    run(sh, &u, NULL, &open_u);
    assert_int_equal(open_a, open_u);
    if (!(ea <= tol))
        fail_msg("%s tol %g: adaptive error %g", sh->name, tol, ea);
    /* the box: G = twice the square grid of A triangles */
    size_t gu_top = largest_under(sh, 0, 1, A), gv_top = largest_under(sh, 1, 1, A);
    if (!gu_top || !gv_top)
        return; /* even 1 x 1 needs A triangles */
    size_t sq = 1;
    while (uniform(sh, sq + 1, sq + 1, NULL) < A)
        ++sq;
    size_t Gu = 2 * sq < gu_top ? 2 * sq : gu_top, Gv = 2 * sq < gv_top ? 2 * sq : gv_top;
    /* gu <= Gu: gv >= v_lb; gu > Gu: gv <= largest_under(Gu + 1), which must fail at gu_top */
    size_t v_lb = smallest_passing(sh, 1, Gu, gv_top, tol);
    size_t u_lb = smallest_passing(sh, 0, Gv, gu_top, tol);
    if (Gu < gu_top) {
        size_t g = largest_under(sh, 1, Gu + 1, A);
        if (g && uniform_passes(sh, gu_top, g, tol))
            fail_msg("%s tol %g: uniform %zu x %zu passes with fewer than %zu", sh->name, tol,
                     gu_top, g, A);
    }
    if (Gv < gv_top) {
        size_t g = largest_under(sh, 0, Gv + 1, A);
        if (g && uniform_passes(sh, g, gv_top, tol))
            fail_msg("%s tol %g: uniform %zu x %zu passes with fewer than %zu", sh->name, tol, g,
                     gv_top, A);
    }
    size_t runs = 0;
    for (size_t gu = u_lb; gu <= Gu; ++gu)
        for (size_t gv = v_lb; gv <= Gv; ++gv) {
            double e;
            size_t c = uniform(sh, gu, gv, &e);
            if (c >= A)
                break;
            runs++;
            if (e <= tol)
                fail_msg("%s tol %g: adaptive %zu triangles (error %g), uniform %zu x %zu "
                         "%zu (error %g)",
                         sh->name, tol, A, ea, gu, gv, c, e);
        }
    print_message("%s tol %g: adaptive %zu (error %.4g); no uniform grid under it passes "
                  "(box %zu..%zu x %zu..%zu, %zu grids run)\n",
                  sh->name, tol, A, ea, u_lb, Gu, v_lb, Gv, runs);
}

static const double tols[3] = {1e-2, 3e-3, 1e-3};

static void test_sphere(void **state)
{
    (void)state;
    double ku[12], kv[12], P[135], W[45];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s), GEOM_OK);
    shape sh = {"sphere", &s, 1};
    for (int t = 0; t < 3; ++t)
        check_shape(&sh, tols[t]);
}

static void test_torus(void **state)
{
    (void)state;
    double ku[12], kv[12], P[243], W[81];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_torus(NULL, 2.0, 0.5, ku, kv, P, W, &s), GEOM_OK);
    shape sh = {"torus", &s, 1};
    for (int t = 0; t < 3; ++t)
        check_shape(&sh, tols[t]);
}

static void test_teapot(void **state)
{
    (void)state;
    geom_surface_set *set = tess_test_teapot();
    shape sh = {"teapot", geom_surface_set_data(set), geom_surface_set_count(set)};
    for (int t = 0; t < 2; ++t) /* 1e-3: the box takes minutes */
        check_shape(&sh, tols[t]);
    geom_surface_set_destroy(set);
}

/* Where a per-span uniform grid has fewer triangles than the adaptive
 * result, the tessellator returns it: stats name the grid, and the result
 * is exactly uniform mode's at that grid (same triangles, same error),
 * within the tolerance. Returns 1 if a uniform grid was chosen. */
static int check_chosen(const shape *sh, double tol)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = tol;
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    geom_error_report rep;
    geom_surface_tess_stats st;
    assert_int_equal(geom_surface_tessellate(sh->s, sh->n, &o, m, &rep, &st, NULL), GEOM_OK);
    geom_mesh_destroy(m);
    assert_true(rep.max_error <= tol);
    if (!st.uniform_u)
        return 0;
    double e;
    size_t n = uniform(sh, st.uniform_u, st.uniform_v, &e);
    print_message("%s tol %g: uniform %u x %u chosen, %zu triangles, error %g\n", sh->name, tol,
                  st.uniform_u, st.uniform_v, st.triangles, rep.max_error);
    assert_int_equal(n, st.triangles);
    assert_true(e == rep.max_error);
    return 1;
}

/* data/surfaces.json's "hill": bicubic B-spline, 3 x 2 spans. */
static const double hill_ku[10] = {0, 0, 0, 0, 1, 2, 3, 3, 3, 3};
static const double hill_kv[9] = {0, 0, 0, 0, 1, 2, 2, 2, 2};
static const double hill_z[6][5] = {{0, 0.2, 0.4, 0.2, 0},     {0.1, 0.8, 1.2, 0.8, 0.1},
                                    {0.2, 1.1, 2, 1.1, 0.2},   {0.1, 0.9, 1.5, 0.9, 0.1},
                                    {0, 0.3, 0.6, 0.3, 0},     {0, 0, 0.1, 0, 0}};

static void test_uniform_chosen(void **state)
{
    (void)state;
    double P[90];
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 5; ++j) {
            P[3 * (i * 5 + j)] = 4.0 + i;
            P[3 * (i * 5 + j) + 1] = j;
            P[3 * (i * 5 + j) + 2] = hill_z[i][j];
        }
    geom_nurbs_surface hill = {3, 3, 6, 5, hill_ku, hill_kv, P, NULL};
    double ku[12], kv[12], TP[243], W[81];
    geom_nurbs_surface torus;
    assert_int_equal(geom_surface_torus(NULL, 2.0, 0.5, ku, kv, TP, W, &torus), GEOM_OK);
    shape sh[2] = {{"hill", &hill, 1}, {"torus", &torus, 1}};
    static const double tl[6] = {0.05, 0.04, 0.03, 0.012, 0.008, 0.005};
    int chosen = 0;
    for (int k = 0; k < 2; ++k)
        for (int t = 0; t < 6; ++t)
            chosen += check_chosen(&sh[k], tl[t]);
    /* the hill at 0.05 takes 2 x 6 per span (144 triangles) */
    assert_true(chosen >= 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_torus),
        cmocka_unit_test(test_teapot),
        cmocka_unit_test(test_uniform_chosen),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
