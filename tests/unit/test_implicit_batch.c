/*
 * The batch evaluators of expressions and volumes against their single-point
 * functions, bit for bit: geom_implicit_expr_eval_many (blocks of points
 * with operands in place, AVX2/AVX-512 clones) against
 * geom_implicit_expr_eval, and geom_implicit_volume_eval_many (the block
 * trilinear interpolator) against geom_implicit_volume_eval, over points
 * inside and outside the domain, on sample positions and cell faces, and
 * NaN/Inf coordinates; every operation, constants folded at run time (t),
 * block tails and programs deeper than the block stack.
 */
#include "unit/test_util.h"

#include <float.h>
#include <string.h>

#include "geom/implicit.h"

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;

static double urand(void) { return test_urand(&rng_state); }

/* n points in [-lo, hi]^3 with some special coordinates mixed in. */
static double *points(size_t n, double lo, double hi)
{
    double *p = malloc(3 * n * sizeof(double));
    assert_non_null(p);
    static const double special[] = {NAN, INFINITY, -INFINITY, 0.0, -0.0, 1e300, -1e300,
                                     1e-310, 0.5, 1.0};
    for (size_t i = 0; i < 3 * n; i++) {
        p[i] = lo + (hi - lo) * urand();
        if (i % 37 == 5)
            p[i] = special[(i / 37) % (sizeof special / sizeof special[0])];
        if (i % 41 == 7)
            p[i] = floor(p[i]); /* sample positions and cell faces */
    }
    return p;
}

static const char *const exprs[] = {
    "sqrt(x*x + y*y + z*z) - 1", "x + y - z", "x*y*z", "x/y", "1/(x - 0.1)", "x^2", "x^3",
    "x^4 - y^5", "x^-2", "sqrt(x)", "log(x)", "exp(x*y)", "sin(3*x) + cos(2*y)", "tan(x)",
    "abs(x - y)", "-x", "min(x, y, z)", "max(x*y, z)", "clamp(x*3, -1, 1)", "clamp(t, x, y)",
    "atan2(y, x)", "pow(x, y)", "pow(abs(x), y)", "x^0.5", "2^x", "t", "t * 2 + x",
    "sin(t) * x - cos(t)", "min(t, 1) + max(x, t)", "sqrt(t) / (x - t)", "(t + 1)^3 * y",
    "atan2(t, x) + pow(t, y) + t^2", "sphere(1)", "sphere(t)", "sphere(0.3, 0.1, -0.2, 0.7)",
    "ellipsoid(1, 0.5, 2)", "torus(1, 0.3)", "box(0.5, 0.7, 0.2)", "cylinder(0.5, 0.8)",
    "plane(1, -2, 0.5, 0.1)", "capsule(-1, 0, 0, 1, 0.5, 0, 0.2)", "gyroid()", "gyroid(3)",
    "gyroid(4, 0.2)", "x + gyroid()", "smooth_union(sphere(0.5), box(0.3, 0.3, 0.3), 0.2)",
    "smooth_intersection(sphere(0.8), gyroid(5), t)",
    "smooth_difference(box(1, 1, 1), sphere(1.2), 0.3)", "x - x", "(x + 1e16) - 1e16",
    "1e300 * x * y", "x / (y*y)", "sqrt(x) + sqrt(-x)", "pow(x, 0)", "pow(0, x)",
    "x^(y*2)", "x*(y*(z*(x*(y*(z*(x*(y+1)+2)+3)+4)+5)+6)+7)",
    /* sums of products fused into one step, with and without the tail */
    "x*x + y*y", "x*y - z*z", "2*x + 3*y - z*0.5", "x*2 - y*t + z*z", "x*y - z*x - y*y",
    "sqrt(x*x + y*y) - 0.5", "abs(x*y - z*3) * 2", "sqrt(x*x - y*y + z*z) / 3",
    "sqrt(x*x + y*y + z*z) + 1e-300", "x + sqrt(x*x + y*y + z*z) - 1",
    "sqrt(1*x*x + 2*y*y + 3*z*z) - 1", "(x*x + y*y + z*z) * (x*y + y*z + z*x)",
    "sqrt((x-0.1)*(x-0.1) + (y+0.2)*(y+0.2) + z*z) - 0.7",
    /* squares written x^2 and pow(x, 2), fused as x*x; distance shapes */
    "x^2 + y^2 + z^2", "sqrt(x^2 + y^2 + z^2) - 1", "sqrt(pow(x, 2) + y*y + z^2) * 3",
    "x*x + y*y + z*z", "sqrt(x*x + y*y + z*z)", "sqrt(x*x + y*y + z*z) / 0.3",
    "sqrt(x*x + y*y + z*z) + 1", "(x*x + y*y + z*z) - 1e-300", "x^2 - y^2", "x^2*3 + y",
    "sqrt(x^2 + y^2) - 0.5", "(x - 0.5)^2 + (y + 1)^2 + z^2 - 1", "x^2 + y*y + z^2 - 1",
    "sqrt(z*z + y*y + x*x) - 1", "sqrt(x*x + y*y + z*z) - t", "sphere(0.7)",
    /* the primitives with a lane loop of their own in the gradient batch:
     * centred (the torus's centre and axis among the points below),
     * arguments of t, arguments that vary from point to point */
    "torus(0.3, 0.1, -0.2, 1, 0.3)", "torus(t, 0.3)", "torus(1 + x*y, z)", "torus(0, 0)",
    "sphere(x*0.5)", "sphere(0.3, 0.1, -0.2, t)", "ellipsoid(0.3, 0.1, -0.2, 1, 0.5, 2)",
    "ellipsoid(x, 1, 0)", "box(0.3, 0.1, -0.2, 0.5, 0.7, 0.2)", "box(x, 0.5, y)",
    "cylinder(0.3, 0.1, -0.2, 0.5, 0.8)", "cylinder(z, x)", "plane(x, 0, 1, y)",
    "min(torus(1, 0.3), box(0.5, 0.5, 0.5)) + sphere(0.3, 0.1, -0.2, 0.4)",
    /* capsule and the gyroids (the gradient batch unrolls every primitive
     * into its operations): point-dependent arguments, a zero-length
     * segment (den = 0), the time */
    "capsule(x, 0, 0, 1, y, 0, 0.2)", "capsule(0.3, 0.1, -0.2, 0.3, 0.1, -0.2, 0.5)",
    "capsule(0, 0, 0, 0, 0, t, z)", "gyroid(x + 3)", "gyroid(t, z)", "gyroid(0)",
    "smooth_union(capsule(-1, 0, 0, 1, 0.5, 0, t), gyroid(4, 0.2), 0.3)",
    /* the sine and cosine of one operand in one step, either first */
    "sin(x) * cos(x)", "cos(y) - sin(y) + sin(y)", "sin(z) + cos(z + 1) + cos(z)",
};

/* A program n levels deep: x+(x+(...(x)...)). */
static char *nested(int n)
{
    char *s = malloc((size_t)n * 4 + 2);
    assert_non_null(s);
    size_t k = 0;
    for (int i = 0; i < n; i++) {
        memcpy(s + k, "x+(", 3);
        k += 3;
    }
    s[k++] = 'x';
    for (int i = 0; i < n; i++)
        s[k++] = ')';
    s[k] = '\0';
    return s;
}

static void check_expr(geom_implicit_expr *e, const char *text, size_t n, const double *p,
                       double *out)
{
    geom_implicit_expr_eval_many(e, n, p, out);
    for (size_t i = 0; i < n; i++) {
        double v = geom_implicit_expr_eval(e, &p[3 * i]);
        if (!same_bits_or_nan(v, out[i]))
            fail_msg("%s at point %zu (%g, %g, %g): batch %.17g, single %.17g", text, i,
                     p[3 * i], p[3 * i + 1], p[3 * i + 2], out[i], v);
    }
}

static void test_expr_batch_bitwise(void **state)
{
    (void)state;
    /* full blocks of 64 and tails of every length up to a block */
    static const size_t counts[] = {1, 63, 64, 65, 127, 128, 1000, 4099};
    double *p = points(4099, -2.5, 2.5), *out = malloc(4099 * sizeof(double));
    assert_non_null(out);
    for (size_t k = 0; k < sizeof exprs / sizeof exprs[0]; k++) {
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(exprs[k], strlen(exprs[k]), NULL, &e, NULL),
                         GEOM_OK);
        static const double times[] = {0.25, -1.5, NAN};
        for (size_t ti = 0; ti < 3; ti++) {
            geom_implicit_expr_set_time(e, times[ti]);
            for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++)
                check_expr(e, exprs[k], counts[c], p, out);
        }
        geom_implicit_expr_destroy(e);
    }
    /* every alignment of the points and of the output: the blocks start at
     * a cache line of p after a few single points */
    char *raw = malloc(3 * 4099 * sizeof(double) + 64), *rawo = malloc(4099 * sizeof(double) + 64);
    assert_non_null(raw);
    assert_non_null(rawo);
    static const char *few[] = {"sqrt(x*x + y*y + z*z) - 1", "sphere(0.5) + x", "x*y - z"};
    for (size_t k = 0; k < sizeof few / sizeof few[0]; k++) {
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(few[k], strlen(few[k]), NULL, &e, NULL),
                         GEOM_OK);
        for (size_t off = 0; off < 64; off += 8)
            for (size_t ooff = 0; ooff < 64; ooff += 8 + 16 * (off > 0)) {
                double *q = (double *)(void *)(raw + off), *o = (double *)(void *)(rawo + ooff);
                memcpy(q, p, 3 * 4099 * sizeof(double));
                for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++)
                    check_expr(e, few[k], counts[c], q, o);
            }
        geom_implicit_expr_destroy(e);
    }
    free(raw);
    free(rawo);
    /* outputs large enough to be written with non-temporal stores, with a
     * tail and misaligned outputs */
    size_t big = (1u << 19) + 77;
    double *pb = points(big, -3.0, 3.0), *ob = malloc((big + 1) * sizeof(double));
    assert_non_null(ob);
    static const char *bigs[] = {"sqrt(x*x + y*y + z*z) - 1", "x*y - z", "sin(x) + y", "2"};
    for (size_t k = 0; k < sizeof bigs / sizeof bigs[0]; k++) {
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(bigs[k], strlen(bigs[k]), NULL, &e, NULL),
                         GEOM_OK);
        check_expr(e, bigs[k], big, pb, ob);
        check_expr(e, bigs[k], big - 3, pb + 3, ob + 1);
        geom_implicit_expr_destroy(e);
    }
    free(pb);
    free(ob);
    /* stacks around the block evaluator's depth and beyond */
    static const int depths[] = {20, 23, 24, 25, 40, 70};
    for (size_t d = 0; d < sizeof depths / sizeof depths[0]; d++) {
        char *s = nested(depths[d]);
        geom_implicit_expr_options opt = {NULL, 0, 200};
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(s, strlen(s), &opt, &e, NULL), GEOM_OK);
        check_expr(e, s, 1000, p, out);
        geom_implicit_expr_destroy(e);
        free(s);
    }
    free(p);
    free(out);
}

/* geom_implicit_expr_eval_grad_many against geom_implicit_expr_eval_grad,
 * values and gradients bit for bit (NaN where it gives NaN), and with the
 * gradients not wanted, over every expression above. */
static void check_grad(geom_implicit_expr *e, const char *text, size_t n, const double *p,
                       double *val, double *grd)
{
    geom_implicit_expr_eval_grad_many(e, n, p, val, grd);
    for (size_t i = 0; i < n; i++) {
        double g[3];
        double v = geom_implicit_expr_eval_grad(e, &p[3 * i], g);
        int same = same_bits_or_nan(v, val[i]);
        for (int a = 0; a < 3; a++)
            same &= same_bits_or_nan(g[a], grd[3 * i + a]);
        if (!same)
            fail_msg("%s at point %zu (%g, %g, %g): batch %.17g (%.17g, %.17g, %.17g), "
                     "single %.17g (%.17g, %.17g, %.17g)",
                     text, i, p[3 * i], p[3 * i + 1], p[3 * i + 2], val[i], grd[3 * i],
                     grd[3 * i + 1], grd[3 * i + 2], v, g[0], g[1], g[2]);
    }
    geom_implicit_expr_eval_grad_many(e, n, p, val, NULL);
    for (size_t i = 0; i < n; i++) {
        double g[3];
        if (!same_bits_or_nan(geom_implicit_expr_eval_grad(e, &p[3 * i], g), val[i]))
            fail_msg("%s at point %zu: value without gradients %.17g", text, i, val[i]);
    }
}

static void test_expr_grad_batch_bitwise(void **state)
{
    (void)state;
    static const size_t counts[] = {1, 15, 16, 17, 63, 64, 65, 127, 1000, 4099};
    double *p = points(4099, -2.5, 2.5), *val = malloc(4099 * sizeof(double));
    double *grd = malloc(3 * 4099 * sizeof(double));
    assert_non_null(val);
    assert_non_null(grd);
    /* zeros of every sign in every coordinate: the derivatives' zero signs */
    static const double zs[] = {0.0, -0.0, 1e-310, -1e-310, 1e200, -1e200};
    for (size_t i = 0; i < 216; i++) {
        p[3 * i] = zs[i % 6];
        p[3 * i + 1] = zs[(i / 6) % 6];
        p[3 * i + 2] = zs[(i / 36) % 6];
    }
    /* the offset primitives' centre (0.3, 0.1, -0.2) and axis, and
     * non-finite coordinates */
    static const double ed[][3] = {{0.3, 0.1, -0.2}, {0.3, 0.1, 0.5}, {0.3, 0.1, -1e200},
                                   {NAN, 0, 0}, {0, NAN, 0}, {0, 0, NAN}, {INFINITY, 0, 0},
                                   {0, -INFINITY, 0}, {0, 0, INFINITY}, {INFINITY, INFINITY, 1},
                                   {0, 0, 1}, {0, 0, -1e-310}, {1, 0, 0}, {-1, 0, 0.3}};
    for (size_t i = 0; i < sizeof ed / sizeof ed[0]; i++)
        memcpy(&p[3 * (216 + i)], ed[i], sizeof ed[i]);
    for (size_t k = 0; k < sizeof exprs / sizeof exprs[0]; k++) {
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(exprs[k], strlen(exprs[k]), NULL, &e, NULL),
                         GEOM_OK);
        static const double times[] = {0.25, -1.5, NAN};
        for (size_t ti = 0; ti < 3; ti++) {
            geom_implicit_expr_set_time(e, times[ti]);
            for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++)
                check_grad(e, exprs[k], counts[c], p, val, grd);
            check_grad(e, exprs[k], 999, p + 3, val + 1, grd + 5); /* unaligned */
        }
        geom_implicit_expr_destroy(e);
    }
    /* programs deeper than the block stack */
    static const int depths[] = {20, 23, 24, 25, 40, 70};
    for (size_t d = 0; d < sizeof depths / sizeof depths[0]; d++) {
        char *s = nested(depths[d]);
        geom_implicit_expr_options opt = {NULL, 0, 200};
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(s, strlen(s), &opt, &e, NULL), GEOM_OK);
        check_grad(e, s, 1000, p, val, grd);
        geom_implicit_expr_destroy(e);
        free(s);
    }
    free(p);
    free(val);
    free(grd);
}

/* An allocator that fails once its budget of allocations is spent (armed),
 * for the gradient batch's unrolling: when it cannot allocate, the points
 * go one by one, the same bits. */
static int alloc_armed, alloc_budget, alloc_failed;
static void *budget_alloc(void *user, size_t size)
{
    (void)user;
    if (alloc_armed && alloc_budget-- <= 0) {
        alloc_failed = 1;
        return NULL;
    }
    return malloc(size);
}
static void *budget_realloc(void *user, void *p, size_t old_size, size_t size)
{
    (void)user;
    (void)old_size;
    if (alloc_armed && alloc_budget-- <= 0) {
        alloc_failed = 1;
        return NULL;
    }
    return realloc(p, size);
}
static void budget_free(void *user, void *p, size_t size)
{
    (void)user;
    (void)size;
    free(p);
}

static void test_expr_grad_batch_nomem(void **state)
{
    (void)state;
    static const geom_allocator al = {budget_alloc, budget_realloc, budget_free, NULL};
    const char *texts[] = {"smooth_union(capsule(-1, 0, 0, 1, 0.5, 0, 0.2), gyroid(4, 0.2), 0.3)",
                           "torus(1, 0.3) + sin(x) * cos(x)"};
    enum { NP = 100 };
    double *p = points(NP, -2.0, 2.0), val[NP], grd[3 * NP];
    for (size_t t = 0; t < sizeof texts / sizeof texts[0]; t++) {
        geom_implicit_expr_options opt = {&al, 0, 0};
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(texts[t], strlen(texts[t]), &opt, &e, NULL),
                         GEOM_OK);
        int failures = 0;
        for (int budget = 0; budget < 200; budget++) {
            alloc_armed = 1;
            alloc_budget = budget;
            alloc_failed = 0;
            check_grad(e, texts[t], NP, p, val, grd);
            alloc_armed = 0;
            failures += alloc_failed;
            if (!alloc_failed)
                break;
        }
        assert_true(failures > 3); /* the unrolling allocates several times */
        assert_false(alloc_failed); /* and succeeds with enough memory */
        geom_implicit_expr_destroy(e);
    }
    free(p);
}

/* geom_implicit_expr_eval_bounds_many: every box exactly the single call
 * (bounds bitwise, definedness), boxes flat, unbounded, outside a domain
 * and invalid (NaN bound, lo > hi: GEOM_ERR_INVALID_ARG, the other boxes
 * still written). */
static void test_expr_bounds_many(void **state)
{
    (void)state;
    enum { NB = 300 };
    static double lo[3 * NB], hi[3 * NB], out[2 * NB];
    static int defined[NB];
    const char *texts[] = {"torus(1, 0.3)", "sqrt(x) - y", "log(x + y) * z",
                           "smooth_union(sphere(0.5), capsule(0, 0, 0, 1, 1, 1, 0.1), 0.2)",
                           "gyroid(4, 0.2) + t"};
    static double p[3 * NB], w[3 * NB];
    for (size_t i = 0; i < 3 * NB; i++) {
        p[i] = 4.0 * urand() - 2.0;
        w[i] = 0.7 * urand();
        lo[i] = p[i] - (i % 11 == 0 ? 0.0 : fabs(w[i]));
        hi[i] = p[i] + (i % 13 == 0 ? INFINITY : fabs(w[i]));
    }
    lo[3 * 7] = -INFINITY;
    for (size_t t = 0; t < sizeof texts / sizeof texts[0]; t++) {
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(texts[t], strlen(texts[t]), NULL, &e, NULL),
                         GEOM_OK);
        for (int bad = 0; bad < 2; bad++) {
            double keep = lo[3 * 5 + 1];
            if (bad)
                lo[3 * 5 + 1] = hi[3 * 5 + 1] + 1.0; /* lo > hi in box 5 */
            memset(defined, 0x55, sizeof defined);
            assert_int_equal(geom_implicit_expr_eval_bounds_many(e, NB, lo, hi, out, defined),
                             bad ? GEOM_ERR_INVALID_ARG : GEOM_OK);
            for (size_t i = 0; i < NB; i++) {
                double want[2];
                int wd = -1;
                geom_status st = geom_implicit_expr_eval_bounds(e, lo + 3 * i, hi + 3 * i, want, &wd);
                assert_int_equal(st, bad && i == 5 ? GEOM_ERR_INVALID_ARG : GEOM_OK);
                assert_true(same_bits_or_nan(out[2 * i], want[0]));
                assert_true(same_bits_or_nan(out[2 * i + 1], want[1]));
                assert_int_equal(defined[i], wd);
            }
            lo[3 * 5 + 1] = keep;
        }
        lo[3 * 9] = NAN;
        assert_int_equal(geom_implicit_expr_eval_bounds_many(e, NB, lo, hi, out, defined),
                         GEOM_ERR_INVALID_ARG);
        assert_true(isnan(out[18]) && isnan(out[19]) && defined[9] == 0);
        lo[3 * 9] = p[3 * 9] - fabs(w[3 * 9]);
        assert_int_equal(geom_implicit_expr_eval_bounds_many(e, 0, NULL, NULL, NULL, NULL),
                         GEOM_OK);
        assert_int_equal(geom_implicit_expr_eval_bounds_many(e, 1, lo, hi, NULL, defined),
                         GEOM_ERR_INVALID_ARG);
        geom_implicit_expr_destroy(e);
    }
    assert_int_equal(geom_implicit_expr_eval_bounds_many(NULL, 1, lo, hi, out, defined),
                     GEOM_ERR_INVALID_ARG);
}

/* x^2 and pow(x, 2) are x*x (the correctly rounded square; the C library's
 * pow(x, 2.0) is not always: glibc's pow is within 1 ulp, and clang does not
 * fold it to x*x, so it is not compared): the single-point evaluator and the
 * batch (where the square fuses into sums of squares like x*x) agree with
 * a*a bit for bit over edge values (signed zeros, subnormals,
 * squares that overflow or underflow, infinities, NaN) and random values,
 * 27-bit ones among them (exact squares) and the sum of three squares. */
static void test_square_is_product(void **state)
{
    (void)state;
    enum { N = 4096 };
    double *p = malloc(3 * N * sizeof(double)), *out = malloc(N * sizeof(double));
    assert_non_null(p);
    assert_non_null(out);
    static const double edge[] = {0.0, -0.0, DBL_TRUE_MIN, -DBL_TRUE_MIN, 1e-310, -1e-310,
                                  DBL_MIN, 1e-160, 1.5e-154, 1e154, 1.34e154, 1e200, -1e200,
                                  DBL_MAX, -DBL_MAX, INFINITY, -INFINITY, NAN, -NAN, 1.0,
                                  -1.0, 0.1, 3.0, 1.0 + DBL_EPSILON, 1.0 - DBL_EPSILON / 2};
    size_t ne = sizeof edge / sizeof edge[0];
    for (size_t i = 0; i < 3 * N; i++) {
        double u = 4.0 * urand() - 2.0;
        if (i % 3 == 1)
            u = ldexp(floor(ldexp(u, 26)), -26); /* 27 bits: exact squares */
        p[i] = i < 3 * ne ? edge[(i / 3 + i % 3 * 7) % ne] : u * pow(10.0, floor(urand() * 40 - 20));
    }
    static const char *const sq[] = {"x^2", "pow(x, 2)", "x*x", "y^2", "z^2"};
    for (size_t k = 0; k < sizeof sq / sizeof sq[0]; k++) {
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(sq[k], strlen(sq[k]), NULL, &e, NULL),
                         GEOM_OK);
        int axis = sq[k][0] == 'y' ? 1 : sq[k][0] == 'z' ? 2 : 0;
        geom_implicit_expr_eval_many(e, N, p, out);
        for (size_t i = 0; i < N; i++) {
            double a = p[3 * i + axis], prod = a * a;
            double v = geom_implicit_expr_eval(e, &p[3 * i]);
            if (!same_bits_or_nan(v, prod) || !same_bits_or_nan(out[i], prod))
                fail_msg("%s at %.17g: single %.17g, batch %.17g, a*a %.17g", sq[k], a, v,
                         out[i], prod);
        }
        geom_implicit_expr_destroy(e);
    }
    /* sums of squares written with ^, *, pow: the same bits as one another */
    static const char *const sums[] = {"x^2 + y^2 + z^2", "x*x + y*y + z*z",
                                       "pow(x, 2) + y^2 + z*z"};
    double *ref = malloc(N * sizeof(double));
    assert_non_null(ref);
    for (size_t k = 0; k < sizeof sums / sizeof sums[0]; k++) {
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(sums[k], strlen(sums[k]), NULL, &e, NULL),
                         GEOM_OK);
        geom_implicit_expr_eval_many(e, N, p, out);
        for (size_t i = 0; i < N; i++) {
            const double *q = &p[3 * i];
            double want = (q[0] * q[0] + q[1] * q[1]) + q[2] * q[2];
            if (k == 0)
                ref[i] = out[i];
            if (!same_bits_or_nan(out[i], want) || !same_bits_or_nan(out[i], ref[i]) ||
                !same_bits_or_nan(geom_implicit_expr_eval(e, q), want))
                fail_msg("%s at point %zu: batch %.17g, want %.17g", sums[k], i, out[i], want);
        }
        geom_implicit_expr_destroy(e);
    }
    free(ref);
    free(p);
    free(out);
}

static geom_implicit_volume *random_volume(size_t nx, size_t ny, size_t nz,
                                           geom_implicit_scalar type, const double sp[3],
                                           const double org[3])
{
    geom_implicit_volume_desc d;
    memset(&d, 0, sizeof d);
    d.dims[0] = nx, d.dims[1] = ny, d.dims[2] = nz;
    d.type = type;
    for (int a = 0; a < 3; a++) {
        d.spacing[a] = sp[a];
        d.origin[a] = org[a];
    }
    geom_implicit_volume *v = NULL;
    assert_int_equal(geom_implicit_volume_create(&d, NULL, &v), GEOM_OK);
    size_t m = nx * ny * nz;
    void *data = geom_implicit_volume_data(v);
    for (size_t i = 0; i < m; i++) {
        double s = 2.0 * urand() - 1.0;
        if (i % 53 == 11)
            s = NAN; /* a NaN sample must not leak into its neighbours' values */
        if (i % 97 == 13)
            s = INFINITY;
        if (type == GEOM_IMPLICIT_SCALAR_F32)
            ((float *)data)[i] = (float)s;
        else
            ((double *)data)[i] = s;
    }
    return v;
}

static void test_volume_batch_bitwise(void **state)
{
    (void)state;
    static const size_t dims[][3] = {{32, 32, 32}, {5, 7, 3}, {2, 2, 2}, {1, 9, 4}, {6, 1, 1}};
    static const double sps[][3] = {{1, 1, 1}, {0.5, 2.0, 0.3}, {0, 0, 0}, {1e-3, 7, 1},
                                    {0x1p-30, 0x1p20, 4.0}};
    static const double orgs[][3] = {{0, 0, 0}, {-1.25, 0.5, 3}, {1e8, -1e8, 0.1}};
    size_t n = 2000;
    double *out = malloc(n * sizeof(double));
    assert_non_null(out);
    for (int type = GEOM_IMPLICIT_SCALAR_F32; type <= GEOM_IMPLICIT_SCALAR_F64; type++)
        for (size_t di = 0; di < sizeof dims / sizeof dims[0]; di++)
            for (size_t si = 0; si < sizeof sps / sizeof sps[0]; si++)
                for (size_t oi = 0; oi < sizeof orgs / sizeof orgs[0]; oi++) {
                    const size_t *dm = dims[di];
                    geom_implicit_volume *v = random_volume(
                        dm[0], dm[1], dm[2], (geom_implicit_scalar)type, sps[si], orgs[oi]);
                    double *p = malloc(3 * n * sizeof(double));
                    assert_non_null(p);
                    /* in sample units around the box, some points well outside */
                    double *q = points(n, -0.3, 1.3);
                    for (size_t i = 0; i < 3 * n; i++) {
                        int a = (int)(i % 3);
                        double s = sps[si][a] > 0 ? sps[si][a] : 1.0;
                        double u = q[i] * (double)(dm[a] - 1);
                        if (i % 41 == 7)
                            u = floor(u);
                        p[i] = isfinite(q[i]) ? orgs[oi][a] + u * s : q[i];
                    }
                    free(q);
                    geom_implicit_volume_eval_many(v, n, p, out, NULL);
                    for (size_t i = 0; i < n; i++) {
                        double w = geom_implicit_volume_eval(v, &p[3 * i]);
                        if (!same_bits_or_nan(w, out[i]))
                            fail_msg("volume %zux%zux%zu type %d at (%.17g, %.17g, %.17g): "
                                     "batch %.17g, single %.17g",
                                     dm[0], dm[1], dm[2], type, p[3 * i], p[3 * i + 1],
                                     p[3 * i + 2], out[i], w);
                    }
                    /* values and gradients, bitwise geom_implicit_volume_eval_grad */
                    double *gr = malloc(3 * n * sizeof(double));
                    assert_non_null(gr);
                    geom_implicit_volume_eval_many(v, n, p, out, gr);
                    for (size_t i = 0; i < n; i++) {
                        double g1[3];
                        double w = geom_implicit_volume_eval_grad(v, &p[3 * i], g1);
                        int same = same_bits_or_nan(w, out[i]);
                        for (int a = 0; a < 3; a++)
                            same &= same_bits_or_nan(g1[a], gr[3 * i + a]);
                        if (!same)
                            fail_msg("volume %zux%zux%zu type %d at (%.17g, %.17g, %.17g): "
                                     "batch %.17g (%.17g, %.17g, %.17g), single %.17g (%.17g, "
                                     "%.17g, %.17g)",
                                     dm[0], dm[1], dm[2], type, p[3 * i], p[3 * i + 1],
                                     p[3 * i + 2], out[i], gr[3 * i], gr[3 * i + 1],
                                     gr[3 * i + 2], w, g1[0], g1[1], g1[2]);
                    }
                    geom_implicit_volume_eval_many(v, 70, p + 3, out, gr);
                    for (size_t i = 0; i < 70; i++) {
                        double g1[3];
                        geom_implicit_volume_eval_grad(v, &p[3 + 3 * i], g1);
                        for (int a = 0; a < 3; a++)
                            assert_true(same_bits_or_nan(g1[a], gr[3 * i + a]));
                    }
                    free(gr);
                    /* the tail after the last full block, and n = 0 */
                    geom_implicit_volume_eval_many(v, 70, p + 3, out, NULL);
                    for (size_t i = 0; i < 70; i++)
                        assert_true(same_bits_or_nan(geom_implicit_volume_eval(v, &p[3 + 3 * i]),
                                                     out[i]));
                    geom_implicit_volume_eval_many(v, 0, p, out, NULL);
                    free(p);
                    geom_implicit_volume_destroy(v);
                }
    /* NULL volume or points: NaN */
    double p0[3] = {0, 0, 0};
    geom_implicit_volume_eval_many(NULL, 1, p0, out, NULL);
    assert_true(isnan(out[0]));
    free(out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_expr_batch_bitwise),
        cmocka_unit_test(test_expr_grad_batch_bitwise),
        cmocka_unit_test(test_expr_grad_batch_nomem),
        cmocka_unit_test(test_expr_bounds_many),
        cmocka_unit_test(test_square_is_product),
        cmocka_unit_test(test_volume_batch_bitwise),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
