/*
 * Tests of the implicit module's expression compiler and evaluators:
 * values against closed forms, gradients against analytic derivatives and
 * Richardson-extrapolated central differences, interval bounds enclosing
 * 10^4 random point evaluations per expression, syntax errors with exact
 * columns, limits, NaN/Inf rules and allocator use.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/implicit.h"

#define PI 3.14159265358979323846

static geom_implicit_expr *compile_ok(const char *s)
{
    geom_implicit_expr *e = NULL;
    geom_diag d;
    geom_diag_clear(&d);
    geom_status st = geom_implicit_expr_compile(s, strlen(s), NULL, &e, &d);
    if (st != GEOM_OK)
        fail_msg("compile '%s': %s (col %zu)", s, d.message, d.column);
    assert_non_null(e);
    return e;
}

static double ev(const char *s, double x, double y, double z)
{
    geom_implicit_expr *e = compile_ok(s);
    double p[3] = {x, y, z};
    double v = geom_implicit_expr_eval(e, p);
    geom_implicit_expr_destroy(e);
    return v;
}

static void near(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol * (1.0 + fabs(want))))
        fail_msg("%s: got %.17g, want %.17g", what, got, want);
}

/* -------------------------------------------------------------- values */

static void test_arithmetic(void **state)
{
    (void)state;
    assert_true(ev("1+2*3", 0, 0, 0) == 7.0);
    assert_true(ev("(1+2)*3", 0, 0, 0) == 9.0);
    assert_true(ev("2^3^2", 0, 0, 0) == 512.0);
    assert_true(ev("-x^2", 3, 0, 0) == -9.0);
    assert_true(ev("(-2)^3", 0, 0, 0) == -8.0);
    assert_true(ev("x^3", -2, 0, 0) == -8.0);
    assert_true(ev("2^-1", 0, 0, 0) == 0.5);
    assert_true(ev("x^-2", 2, 0, 0) == 0.25);
    assert_true(ev("10 - 4 - 3", 0, 0, 0) == 3.0);
    assert_true(ev("64 / 4 / 2", 0, 0, 0) == 8.0);
    assert_true(ev("--x", 5, 0, 0) == 5.0);
    assert_true(ev("+x", 5, 0, 0) == 5.0);
    assert_true(ev(".5 + 1. + 1e-3 + 2.5E+2", 0, 0, 0) == 0.5 + 1.0 + 1e-3 + 250.0);
    assert_true(ev("x*y - z", 2, 3, 4) == 2.0);
    assert_true(ev("pi", 0, 0, 0) == PI);
    assert_true(ev("e", 0, 0, 0) == exp(1.0));
    assert_true(ev(" \t x\n + \r\n y ", 1, 2, 0) == 3.0);
    near(ev("sqrt(x*x + y*y)", 3, 4, 0), 5.0, 0, "sqrt");
    assert_true(ev("abs(x)", -2.5, 0, 0) == 2.5);
    near(ev("sin(x)", 0.3, 0, 0), sin(0.3), 0, "sin");
    near(ev("cos(x)", 0.3, 0, 0), cos(0.3), 0, "cos");
    near(ev("tan(x)", 0.3, 0, 0), tan(0.3), 0, "tan");
    near(ev("exp(x)", 0.3, 0, 0), exp(0.3), 0, "exp");
    near(ev("log(x)", 0.3, 0, 0), log(0.3), 0, "log");
    near(ev("pow(x, y)", 1.7, 2.3, 0), pow(1.7, 2.3), 0, "pow");
    near(ev("x^0.5", 2, 0, 0), sqrt(2.0), 1e-16, "x^0.5");
    near(ev("atan2(y, x)", -1, 1, 0), 0.75 * PI, 1e-16, "atan2");
    assert_true(ev("min(x, y, z)", 3, 1, 2) == 1.0);
    assert_true(ev("max(x, y, z)", 3, 1, 2) == 3.0);
    assert_true(ev("clamp(x, 0, 1)", 1.5, 0, 0) == 1.0);
    assert_true(ev("clamp(x, 0, 1)", -1.5, 0, 0) == 0.0);
    assert_true(ev("clamp(x, 0, 1)", 0.25, 0, 0) == 0.25);
    near(ev("sin(x)^2 + cos(x)^2", 1.234, 0, 0), 1.0, 1e-15, "pythagoras");
    /* t */
    geom_implicit_expr *e = compile_ok("x + 10*t");
    double p[3] = {1, 0, 0};
    assert_true(geom_implicit_expr_eval(e, p) == 1.0);
    geom_implicit_expr_set_time(e, 0.5);
    assert_true(geom_implicit_expr_eval(e, p) == 6.0);
    assert_int_equal(geom_implicit_expr_variables(e), GEOM_IMPLICIT_VAR_X | GEOM_IMPLICIT_VAR_T);
    geom_implicit_expr_destroy(e);
    /* primitives read the point although no variable is written out */
    e = compile_ok("sphere(1)");
    assert_int_equal(geom_implicit_expr_variables(e),
                     GEOM_IMPLICIT_VAR_X | GEOM_IMPLICIT_VAR_Y | GEOM_IMPLICIT_VAR_Z);
    geom_implicit_expr_destroy(e);
    e = compile_ok("gyroid() + t");
    assert_int_equal(geom_implicit_expr_variables(e), GEOM_IMPLICIT_VAR_X | GEOM_IMPLICIT_VAR_Y |
                                                          GEOM_IMPLICIT_VAR_Z | GEOM_IMPLICIT_VAR_T);
    geom_implicit_expr_destroy(e);
}

static void test_constant_folding(void **state)
{
    (void)state;
    geom_implicit_expr *e = compile_ok("2*3 + sqrt(16) - max(1, 2, 3)");
    assert_int_equal(geom_implicit_expr_size(e), 1);
    double p[3] = {0, 0, 0};
    assert_true(geom_implicit_expr_eval(e, p) == 7.0);
    assert_int_equal(geom_implicit_expr_variables(e), 0);
    geom_implicit_expr_destroy(e);
    /* x ^ 2 becomes an integer power of x: two instructions */
    e = compile_ok("x ^ (1 + 1)");
    assert_int_equal(geom_implicit_expr_size(e), 2);
    geom_implicit_expr_destroy(e);
}

static double hyp3(double a, double b, double c) { return sqrt(a * a + b * b + c * c); }

static void test_primitives(void **state)
{
    (void)state;
    /* sphere */
    assert_true(ev("sphere(1)", 2, 0, 0) == 1.0);
    near(ev("sphere(1, 2, 3, 0.5)", 0.3, -0.7, 1.1), hyp3(0.3 - 1, -0.7 - 2, 1.1 - 3) - 0.5, 1e-15,
         "sphere4");
    /* ellipsoid: zero on the surface, exact for spheres, scaled by min axis */
    near(ev("ellipsoid(1, 2, 3)", 0, 2, 0), 0.0, 1e-15, "ellipsoid on y axis");
    near(ev("ellipsoid(1, 2, 3)", 0, 0, -3), 0.0, 1e-15, "ellipsoid on z axis");
    near(ev("ellipsoid(1, 2, 3)", 2, 0, 0), 1.0, 1e-15, "ellipsoid outside on x");
    near(ev("ellipsoid(2, 2, 2)", 1, 1, 1), sqrt(3.0) - 2.0, 1e-15, "ellipsoid as sphere");
    near(ev("ellipsoid(1, 1, 1, 1, 2, 3)", 1, 3, 1), 0.0, 1e-15, "ellipsoid centred");
    /* torus (axis z) */
    assert_true(ev("torus(2, 0.5)", 2, 0, 0) == -0.5);
    assert_true(ev("torus(2, 0.5)", 0, 0, 0) == 1.5);
    near(ev("torus(2, 0.5)", 0, 3, 1), sqrt(2.0) - 0.5, 1e-15, "torus");
    near(ev("torus(1, 1, 1, 2, 0.5)", 1, 1, 1), 1.5, 1e-15, "torus centred");
    /* box */
    assert_true(ev("box(1, 2, 3)", 0, 0, 0) == -1.0);
    near(ev("box(1, 2, 3)", 2, 3, 4), sqrt(3.0), 1e-15, "box corner region");
    assert_true(ev("box(1, 2, 3)", 0.5, 0, 0) == -0.5);
    assert_true(ev("box(1, 2, 3)", 3, 0, 0) == 2.0);
    assert_true(ev("box(1, 1, 1, 1, 2, 3)", 1, 1, 1) == -1.0);
    /* cylinder */
    assert_true(ev("cylinder(1, 2)", 0, 0, 3) == 1.0);
    near(ev("cylinder(1, 2)", 2, 0, 3), sqrt(2.0), 1e-15, "cylinder rim region");
    assert_true(ev("cylinder(1, 2)", 0, 0, 0) == -1.0);
    near(ev("cylinder(1, 2)", 0, 0.5, 1.9), 1.9 - 2.0, 1e-15, "cylinder near the cap");
    near(ev("cylinder(1, 1, 0, 1, 2)", 1, 2.5, 0), 0.5, 1e-15, "cylinder centred");
    /* plane: n.p <= d inside, normalised */
    assert_true(ev("plane(0, 0, 2, 1)", 7, 7, 3) == 2.5);
    assert_true(ev("plane(3, 4, 0, 5)", 0, 0, 0) == -1.0);
    /* capsule */
    assert_true(ev("capsule(0, 0, 0, 0, 0, 2, 0.5)", 1, 0, 1) == 0.5);
    assert_true(ev("capsule(0, 0, 0, 0, 0, 2, 0.5)", 0, 0, 3) == 0.5);
    assert_true(ev("capsule(0, 0, 0, 0, 0, 2, 0.5)", 0, 0, -1) == 0.5);
    near(ev("capsule(1, 1, 1, 1, 1, 1, 0.5)", 1, 1, 3), 1.5, 1e-15, "capsule degenerate");
    /* gyroid */
    double x = 0.3, y = -1.2, z = 2.1;
    double g = sin(x) * cos(y) + sin(y) * cos(z) + sin(z) * cos(x);
    near(ev("gyroid()", x, y, z), g, 1e-15, "gyroid()");
    double g2 = sin(2 * x) * cos(2 * y) + sin(2 * y) * cos(2 * z) + sin(2 * z) * cos(2 * x);
    near(ev("gyroid(2)", x, y, z), g2 / 2, 1e-15, "gyroid(s)");
    near(ev("gyroid(2, 0.1)", x, y, z), fabs(g2) / 2 - 0.1, 1e-15, "gyroid(s, th)");
    /* CSG */
    assert_true(ev("union(x, y, z)", 3, 1, 2) == 1.0);
    assert_true(ev("intersection(x, y, z)", 3, 1, 2) == 3.0);
    assert_true(ev("difference(x, y)", 3, 5, 0) == 3.0);
    assert_true(ev("difference(x, y)", 3, -5, 0) == 5.0);
    assert_true(ev("difference(x, y, z)", 1, -2, -7) == 7.0);
    /* smooth: equals min when |a - b| >= k; min - k/4 when a == b */
    assert_true(ev("smooth_union(x, y, 0.5)", 1, 2, 0) == 1.0);
    assert_true(ev("smooth_union(x, y, 0.5)", 1, 1, 0) == 1.0 - 0.125);
    double a = 0.3, b = 0.5, k = 0.4, h = fmax(k - fabs(a - b), 0.0);
    near(ev("smooth_union(x, y, 0.4)", a, b, 0), fmin(a, b) - h * h / (4 * k), 1e-15, "smin");
    near(ev("smooth_intersection(x, y, 0.4)", a, b, 0), fmax(a, b) + h * h / (4 * k), 1e-15,
         "smax");
    /* smooth_difference(a, b, k) = -smin(-a, b, k) */
    double ma = -a, hb = fmax(k - fabs(ma - b), 0.0);
    near(ev("smooth_difference(x, y, 0.4)", a, b, 0), -(fmin(ma, b) - hb * hb / (4 * k)), 1e-15,
         "sdiff");
    assert_true(ev("smooth_union(x, y, 0)", 1, 1, 0) == 1.0);
    assert_true(ev("smooth_union(x, y, -1)", 1, 1.5, 0) == 1.0);
}

static void test_nonfinite(void **state)
{
    (void)state;
    assert_true(isnan(ev("sqrt(x)", -1, 0, 0)));
    assert_true(isnan(ev("log(x)", -1, 0, 0)));
    assert_true(ev("log(x)", 0, 0, 0) == -INFINITY);
    assert_true(ev("1/x", 0, 0, 0) == INFINITY);
    assert_true(ev("-1/x", 0, 0, 0) == -INFINITY);
    assert_true(isnan(ev("x/x", 0, 0, 0)));
    assert_true(isnan(ev("x^0.5", -4, 0, 0)));
    /* NaN propagates through min/max/clamp/union (unlike fmin) */
    assert_true(isnan(ev("min(sqrt(x), 1)", -1, 0, 0)));
    assert_true(isnan(ev("max(1, sqrt(x))", -1, 0, 0)));
    assert_true(isnan(ev("clamp(sqrt(x), 0, 1)", -1, 0, 0)));
    assert_true(isnan(ev("union(sphere(1), log(x))", -1, 0, 0)));
    assert_true(isnan(ev("x + 1", NAN, 0, 0)));
    assert_true(ev("exp(x)", 1000, 0, 0) == INFINITY);
    assert_true(ev("exp(x)", -1000, 0, 0) == 0.0);
    /* gradients at special points */
    geom_implicit_expr *e = compile_ok("sphere(1)");
    double p[3] = {0, 0, 0}, g[3];
    assert_true(geom_implicit_expr_eval_grad(e, p, g) == -1.0);
    assert_true(g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0);
    geom_implicit_expr_destroy(e);
    e = compile_ok("abs(x) + abs(y)");
    p[0] = 0.0;
    p[1] = -2.0;
    geom_implicit_expr_eval_grad(e, p, g);
    assert_true(g[0] == 0.0 && g[1] == -1.0 && g[2] == 0.0);
    geom_implicit_expr_destroy(e);
    e = compile_ok("atan2(y, x)");
    p[0] = p[1] = 0.0;
    geom_implicit_expr_eval_grad(e, p, g);
    assert_true(g[0] == 0.0 && g[1] == 0.0);
    geom_implicit_expr_destroy(e);
    /* kink conventions: ties go to the first argument */
    e = compile_ok("min(2*x, y)");
    p[0] = 1.0;
    p[1] = 2.0;
    geom_implicit_expr_eval_grad(e, p, g);
    assert_true(g[0] == 2.0 && g[1] == 0.0);
    geom_implicit_expr_destroy(e);
    e = compile_ok("max(y, 2*x)");
    geom_implicit_expr_eval_grad(e, p, g);
    assert_true(g[0] == 0.0 && g[1] == 1.0);
    geom_implicit_expr_destroy(e);
    e = compile_ok("clamp(3*x, 0, 3)");
    p[0] = 1.0;
    geom_implicit_expr_eval_grad(e, p, g);
    assert_true(g[0] == 3.0);
    p[0] = 1.5;
    geom_implicit_expr_eval_grad(e, p, g);
    assert_true(g[0] == 0.0);
    geom_implicit_expr_destroy(e);
    /* integer power of a negative base: finite gradient */
    e = compile_ok("x^3");
    p[0] = -2.0;
    assert_true(geom_implicit_expr_eval_grad(e, p, g) == -8.0);
    assert_true(g[0] == 12.0 && g[1] == 0.0);
    geom_implicit_expr_destroy(e);
}

/* ----------------------------------------------------------- gradients */

typedef void (*grad_fn)(const double p[3], double g[3]);

static void check_grad(const char *expr, const double p[3], const double want[3], double tol)
{
    geom_implicit_expr *e = compile_ok(expr);
    double g[3];
    double v = geom_implicit_expr_eval_grad(e, p, g);
    assert_true(v == geom_implicit_expr_eval(e, p));
    for (int i = 0; i < 3; i++)
        if (!(fabs(g[i] - want[i]) <= tol * (1.0 + fabs(want[i]))))
            fail_msg("%s at (%g,%g,%g): d/d%c = %.17g, want %.17g", expr, p[0], p[1], p[2],
                     "xyz"[i], g[i], want[i]);
    geom_implicit_expr_destroy(e);
}

static void test_gradient_analytic(void **state)
{
    (void)state;
    double p[3] = {0.7, -0.4, 1.3};
    double x = p[0], y = p[1], z = p[2], w[3];
    /* sphere centred at c: (p - c) / |p - c| */
    double cx = 0.1, cy = 0.2, cz = 0.3, r = hyp3(x - cx, y - cy, z - cz);
    w[0] = (x - cx) / r, w[1] = (y - cy) / r, w[2] = (z - cz) / r;
    check_grad("sphere(0.1, 0.2, 0.3, 1)", p, w, 1e-15);
    /* torus(R, r): q = sqrt(x^2 + y^2) - R; grad = (q x/rho, q y/rho, z) / |(q, z)| */
    double R = 2.0, rho = hypot(x, y), q = rho - R, l = hypot(q, z);
    w[0] = q * x / rho / l, w[1] = q * y / rho / l, w[2] = z / l;
    check_grad("torus(2, 0.5)", p, w, 1e-14);
    /* box outside in the face region of +z: gradient (0, 0, 1) */
    double pb[3] = {0.2, -0.3, 5.0};
    w[0] = 0, w[1] = 0, w[2] = 1;
    check_grad("box(1, 1, 1)", pb, w, 0);
    /* box outside near the corner region: (d+) / |d+| */
    double pc[3] = {2.0, -3.0, 1.5}, d0 = 1.0, d1 = 2.0, d2 = 0.5, dl = hyp3(d0, d1, d2);
    w[0] = d0 / dl, w[1] = -d1 / dl, w[2] = d2 / dl;
    check_grad("box(1, 1, 1)", pc, w, 1e-15);
    /* box inside, nearest face -x */
    double pi_[3] = {-0.9, 0.1, 0.2};
    w[0] = -1, w[1] = 0, w[2] = 0;
    check_grad("box(1, 1, 1)", pi_, w, 0);
    /* plane */
    w[0] = 3.0 / 13.0, w[1] = 4.0 / 13.0, w[2] = 12.0 / 13.0;
    check_grad("plane(3, 4, 12, 1)", p, w, 1e-15);
    /* cylinder side region: radial unit vector */
    w[0] = x / rho, w[1] = y / rho, w[2] = 0;
    double pcyl[3] = {x, y, 0.2};
    check_grad("cylinder(0.5, 1)", pcyl, w, 1e-15);
    /* capsule, middle region: radial from the axis */
    w[0] = x / rho, w[1] = y / rho, w[2] = 0;
    check_grad("capsule(0, 0, -2, 0, 0, 2, 0.1)", p, w, 1e-15);
    /* ellipsoid: min(a,b,c) * (x/a^2, y/b^2, z/c^2) / |(x/a, y/b, z/c)| */
    double a = 1.0, b = 2.0, c = 3.0, L = hyp3(x / a, y / b, z / c);
    w[0] = x / (a * a) / L, w[1] = y / (b * b) / L, w[2] = z / (c * c) / L;
    check_grad("ellipsoid(1, 2, 3)", p, w, 1e-15);
    /* gyroid */
    w[0] = cos(x) * cos(y) - sin(z) * sin(x);
    w[1] = -sin(x) * sin(y) + cos(y) * cos(z);
    w[2] = -sin(y) * sin(z) + cos(z) * cos(x);
    check_grad("gyroid()", p, w, 1e-15);
    /* general formulas */
    w[0] = y * cos(x * y), w[1] = x * cos(x * y), w[2] = exp(z);
    check_grad("sin(x*y) + exp(z)", p, w, 1e-15);
    w[0] = y * z * pow(x, y * z - 1), w[1] = z * log(x) * pow(x, y * z),
    w[2] = y * log(x) * pow(x, y * z);
    check_grad("x^(y*z)", p, w, 1e-14);
    w[0] = 1.0 / (x * x + 1.0) * 0 + -y / (x * x + y * y), w[1] = x / (x * x + y * y), w[2] = 0;
    check_grad("atan2(y, x)", p, w, 1e-15);
    w[0] = 1 / x, w[1] = 0, w[2] = 1 + tan(z) * tan(z);
    check_grad("log(x) + tan(z)", p, w, 1e-15);
    w[0] = -1.0 / (x * x) * 1.0, w[1] = 0, w[2] = 0;
    check_grad("1/x", p, w, 1e-15);
    w[0] = 0.5 / sqrt(x), w[1] = 0, w[2] = 0;
    check_grad("sqrt(x)", p, w, 1e-15);
}

/* Richardson extrapolation of central differences: error O(h^4). */
static double richardson(geom_implicit_expr *e, const double p[3], int axis, double h)
{
    double q[3], r[3];
    double d[2];
    for (int s = 0; s < 2; s++) {
        double hs = s == 0 ? h : h / 2;
        memcpy(q, p, sizeof q);
        memcpy(r, p, sizeof r);
        q[axis] += hs;
        r[axis] -= hs;
        d[s] = (geom_implicit_expr_eval(e, q) - geom_implicit_expr_eval(e, r)) / (2 * hs);
    }
    return (4.0 * d[1] - d[0]) / 3.0;
}

static uint64_t rng_state = 88172645463325252ull;
static double urand(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}
static double urange(double a, double b) { return a + (b - a) * urand(); }

static const char *const smooth_exprs[] = {
    "sphere(0.2, -0.1, 0.3, 1)",
    "torus(1.5, 0.4)",
    "ellipsoid(1, 2, 0.5)",
    "gyroid(2, 0.3)",
    "smooth_union(sphere(1), torus(1, 0.3), 0.5)",
    "smooth_intersection(sphere(1), plane(1, 1, 1, 0.2), 0.3)",
    "smooth_difference(sphere(1), sphere(0.5, 0, 0, 0.6), 0.4)",
    "sin(x*y) * exp(-z^2) + atan2(y, x + 3)",
    "x^3 - 2*x*y + y^2/(1 + z^2) + sqrt(x^2 + 1)",
    "log(2 + cos(x)) * pow(1.5 + sin(y), z)",
    "tan(0.3*x) + cylinder(2, 3) * 0.1",
};

static void test_gradient_richardson(void **state)
{
    (void)state;
    for (size_t k = 0; k < sizeof smooth_exprs / sizeof smooth_exprs[0]; k++) {
        geom_implicit_expr *e = compile_ok(smooth_exprs[k]);
        for (int trial = 0; trial < 50; trial++) {
            double p[3] = {urange(-1.2, 1.2), urange(-1.2, 1.2), urange(-1.2, 1.2)};
            double g[3];
            double v = geom_implicit_expr_eval_grad(e, p, g);
            if (!isfinite(v))
                continue;
            for (int a = 0; a < 3; a++) {
                double fd = richardson(e, p, a, 1e-3);
                /* Kinks (the smooth ops are C^1 only, cylinder is not C^1 at
                 * its rim): compare where the two one-sided estimates agree. */
                double fd2 = richardson(e, p, a, 5e-4);
                if (fabs(fd - fd2) > 1e-7 * (1 + fabs(fd)))
                    continue;
                if (!(fabs(g[a] - fd) <= 1e-7 * (1 + fabs(fd))))
                    fail_msg("%s at (%.17g,%.17g,%.17g) d/d%c: dual %.17g, Richardson %.17g",
                             smooth_exprs[k], p[0], p[1], p[2], "xyz"[a], g[a], fd);
            }
        }
        geom_implicit_expr_destroy(e);
    }
}

/* ----------------------------------------------------------- intervals */

static const char *const interval_exprs[] = {
    "x + y - z", "x*y*z", "x/y", "1/(x - 0.1)", "x^2", "x^3", "x^4 - y^5", "x^-2", "x^-3",
    "sqrt(x)", "log(x)", "log(x*x + 0.01)", "exp(x*y)", "sin(3*x) + cos(2*y)",
    "tan(x)", "abs(x - y)", "min(x, y, z)", "max(x*y, z)", "clamp(x*3, -1, 1)",
    "atan2(y, x)", "atan2(y - 0.3, x + 0.2)", "pow(x, y)", "pow(abs(x), y)", "x^0.5",
    "pow(x, 3)", "2^x", "sphere(1)", "sphere(0.3, 0.1, -0.2, 0.7)", "ellipsoid(1, 0.5, 2)",
    "torus(1, 0.3)", "box(0.5, 0.7, 0.2)", "cylinder(0.5, 0.8)", "plane(1, -2, 0.5, 0.1)",
    "capsule(-1, 0, 0, 1, 0.5, 0, 0.2)", "gyroid()", "gyroid(3)", "gyroid(4, 0.2)",
    "smooth_union(sphere(0.5), box(0.3, 0.3, 0.3), 0.2)",
    "smooth_intersection(sphere(0.8), gyroid(5), 0.1)",
    "smooth_difference(box(1, 1, 1), sphere(1.2), 0.3)",
    "difference(sphere(1), sphere(0.2, 0, 0, 0.8))", "x - x", "(x + 1e16) - 1e16",
    "1e300 * x * y", "exp(100 * x)", "sin(1e7 * x)", "x / (y*y)", "sqrt(x) + sqrt(-x)",
    "pow(x, 0)", "pow(0, x)", "x^(y*2)",
};

static void test_interval_enclosure(void **state)
{
    (void)state;
    size_t checked = 0;
    for (size_t k = 0; k < sizeof interval_exprs / sizeof interval_exprs[0]; k++) {
        geom_implicit_expr *e = compile_ok(interval_exprs[k]);
        for (int box = 0; box < 100; box++) {
            double lo[3], hi[3];
            double scale = box < 30 ? 0.01 : box < 60 ? 0.5 : box < 90 ? 2.0 : 8.0;
            for (int a = 0; a < 3; a++) {
                double c = urange(-2, 2), w = scale * urand();
                lo[a] = c - w;
                hi[a] = c + w;
                if (box % 10 == 3) { /* boxes touching or straddling 0 */
                    lo[a] = box % 20 == 3 ? 0.0 : -w;
                    hi[a] = w;
                }
            }
            double iv[2];
            assert_int_equal(geom_implicit_expr_eval_interval(e, lo, hi, iv), GEOM_OK);
            for (int s = 0; s < 100; s++) {
                double p[3];
                for (int a = 0; a < 3; a++) {
                    double u = urand();
                    /* include the faces and corners */
                    if (s < 8)
                        u = (s >> a) & 1;
                    else if (s < 16)
                        u = (s & 1) ? 0.0 : 1.0;
                    p[a] = lo[a] + u * (hi[a] - lo[a]);
                    if (p[a] > hi[a])
                        p[a] = hi[a];
                }
                double v = geom_implicit_expr_eval(e, p);
                if (!isfinite(v))
                    continue;
                checked++;
                if (!(iv[0] <= v && v <= iv[1]))
                    fail_msg("%s: f(%.17g, %.17g, %.17g) = %.17g outside [%.17g, %.17g] of box "
                             "[%.17g,%.17g]x[%.17g,%.17g]x[%.17g,%.17g]",
                             interval_exprs[k], p[0], p[1], p[2], v, iv[0], iv[1], lo[0], hi[0],
                             lo[1], hi[1], lo[2], hi[2]);
            }
        }
        geom_implicit_expr_destroy(e);
    }
    assert_true(checked > 300000);
}

static void interval_of(const char *s, const double lo[3], const double hi[3], double out[2])
{
    geom_implicit_expr *e = compile_ok(s);
    assert_int_equal(geom_implicit_expr_eval_interval(e, lo, hi, out), GEOM_OK);
    geom_implicit_expr_destroy(e);
}

static void test_interval_cases(void **state)
{
    (void)state;
    double lo[3] = {-2, -1, 0.5}, hi[3] = {3, 1, 2}, r[2];
    /* even powers are never negative */
    interval_of("x^2", lo, hi, r);
    assert_true(r[0] == 0.0 && r[1] >= 9.0 && r[1] < 9.0 + 1e-14);
    interval_of("x^4", lo, hi, r);
    assert_true(r[0] == 0.0 && r[1] >= 81.0 && r[1] < 81.0 + 1e-12);
    interval_of("x^3", lo, hi, r);
    assert_true(r[0] <= -8.0 && r[0] > -8.0 - 1e-12 && r[1] >= 27.0 && r[1] < 27 + 1e-12);
    interval_of("abs(x)", lo, hi, r);
    assert_true(r[0] == 0.0 && r[1] == 3.0);
    /* division by an interval containing 0 */
    interval_of("1/x", lo, hi, r);
    assert_true(r[0] == -INFINITY && r[1] == INFINITY);
    interval_of("1/z", lo, hi, r);
    assert_true(r[0] <= 0.5 && r[0] > 0.5 - 1e-15 && r[1] >= 2.0 && r[1] < 2.0 + 1e-15);
    /* x^-2 around 0: [1/9, inf] */
    interval_of("x^-2", lo, hi, r);
    assert_true(r[0] <= 1.0 / 9 && r[0] > 1.0 / 9 - 1e-15 && r[1] == INFINITY);
    /* sqrt and log domains */
    interval_of("sqrt(x)", lo, hi, r);
    assert_true(r[0] == 0.0 && r[1] >= sqrt(3.0) && r[1] < sqrt(3.0) + 1e-15);
    double nlo[3] = {-4, -3, -2}, nhi[3] = {-1, -1, -1};
    interval_of("sqrt(x)", nlo, nhi, r);
    assert_true(isnan(r[0]) && isnan(r[1]));
    interval_of("log(x)", nlo, nhi, r);
    assert_true(isnan(r[0]) && isnan(r[1]));
    interval_of("log(x)", lo, hi, r);
    assert_true(r[0] == -INFINITY && r[1] >= log(3.0));
    /* NaN inside min: no defined point */
    interval_of("min(sqrt(x), 1)", nlo, nhi, r);
    assert_true(isnan(r[0]));
    /* sin over a box holding a maximum */
    double slo[3] = {1, 0, 0}, shi[3] = {2, 0, 0};
    interval_of("sin(x)", slo, shi, r);
    assert_true(r[1] == 1.0 && r[0] <= sin(1.0) && r[0] > sin(1.0) - 1e-14);
    interval_of("cos(x)", slo, shi, r);
    assert_true(r[0] <= cos(2.0) && r[0] > cos(2.0) - 1e-14 && r[1] >= cos(1.0) &&
                r[1] < cos(1.0) + 1e-14);
    /* a point box gives a narrow interval around the value */
    double p[3] = {0.3, 0.4, 0.5};
    interval_of("sphere(1)", p, p, r);
    double v = sqrt(0.5) - 1;
    assert_true(r[0] <= v && v <= r[1] && r[1] - r[0] < 1e-14);
    /* culling: a sphere far from a box is positive over it */
    double flo[3] = {3, 3, 3}, fhi[3] = {4, 4, 4};
    interval_of("sphere(1)", flo, fhi, r);
    assert_true(r[0] > 0.0 && r[0] <= sqrt(27.0) - 1);
    /* infinite boxes */
    double ilo[3] = {-INFINITY, -INFINITY, -INFINITY}, ihi[3] = {INFINITY, INFINITY, INFINITY};
    interval_of("sin(x)", ilo, ihi, r);
    assert_true(r[0] == -1.0 && r[1] == 1.0);
    interval_of("x^2 + 1", ilo, ihi, r);
    assert_true(r[0] <= 1.0 && r[0] > 0.99 && r[1] == INFINITY);
    /* invalid boxes */
    geom_implicit_expr *e = compile_ok("x");
    double bad[3] = {1, 0, 0};
    double nanb[3] = {NAN, 0, 0};
    assert_int_equal(geom_implicit_expr_eval_interval(e, bad, hi, r), GEOM_OK);
    assert_int_equal(geom_implicit_expr_eval_interval(e, hi, bad, r), GEOM_ERR_INVALID_ARG);
    assert_true(isnan(r[0]));
    assert_int_equal(geom_implicit_expr_eval_interval(e, nanb, hi, r), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_implicit_expr_eval_interval(e, lo, hi, NULL), GEOM_ERR_INVALID_ARG);
    geom_implicit_expr_destroy(e);
}

/* -------------------------------------------------------------- errors */

typedef struct err_case {
    const char *text;
    geom_status status;
    size_t line, column;
    const char *message; /* a substring of the message */
} err_case;

static void test_syntax_errors(void **state)
{
    (void)state;
    static const err_case cases[] = {
        {"1 +", GEOM_ERR_PARSE, 1, 4, "expected a number, a name or '(', found end of input"},
        {"", GEOM_ERR_PARSE, 1, 1, "found end of input"},
        {"sphere(1, 2)", GEOM_ERR_PARSE, 1, 1, "'sphere' takes 1 or 4 arguments, got 2"},
        {"x + torus(1)", GEOM_ERR_PARSE, 1, 5, "'torus' takes 2 or 5 arguments, got 1"},
        {"sqrt(1, 2)", GEOM_ERR_PARSE, 1, 1, "'sqrt' takes 1 argument, got 2"},
        {"max(x)", GEOM_ERR_PARSE, 1, 1, "'max' takes at least 2 arguments, got 1"},
        {"gyroid(1, 2, 3)", GEOM_ERR_PARSE, 1, 1, "'gyroid' takes 0, 1 or 2 arguments, got 3"},
        {"smooth_difference(x, y)", GEOM_ERR_PARSE, 1, 1, "takes 3 arguments, got 2"},
        {"foo(x)", GEOM_ERR_PARSE, 1, 1, "unknown function 'foo'"},
        {"x + w", GEOM_ERR_PARSE, 1, 5, "unknown identifier 'w'"},
        {"2 * spher", GEOM_ERR_PARSE, 1, 5, "unknown identifier 'spher'"},
        {"(x + 1", GEOM_ERR_PARSE, 1, 7, "expected ')' to close '(' at column 1, found end"},
        {"((x) + 1))", GEOM_ERR_PARSE, 1, 10, "unmatched ')'"},
        {"x $ y", GEOM_ERR_PARSE, 1, 3, "unexpected character '$'"},
        {"1e+", GEOM_ERR_PARSE, 1, 1, "expected digits in the exponent"},
        {"1.5.2", GEOM_ERR_PARSE, 1, 4, "malformed number"},
        {"2x", GEOM_ERR_PARSE, 1, 2, "malformed number"},
        {"x y", GEOM_ERR_PARSE, 1, 3, "expected an operator or end of input, found 'y'"},
        {"sin x", GEOM_ERR_PARSE, 1, 5, "expected '(' after the function 'sin', found 'x'"},
        {"x(1)", GEOM_ERR_PARSE, 1, 1, "'x' is not a function"},
        {"min(1, )", GEOM_ERR_PARSE, 1, 8, "found ')'"},
        {"max(1 2)", GEOM_ERR_PARSE, 1, 7,
         "expected ',' or ')' in the arguments of 'max' (opened at column 4), found number '2'"},
        {"x * * y", GEOM_ERR_PARSE, 1, 5, "found '*'"},
        {"x +\n  * y", GEOM_ERR_PARSE, 2, 3, "found '*'"},
        {"1e999", GEOM_ERR_PARSE, 1, 1, "too large"},
        {"x^", GEOM_ERR_PARSE, 1, 3, "found end of input"},
        {"sin(x", GEOM_ERR_PARSE, 1, 6, "opened at column 4"},
        {"\x80", GEOM_ERR_PARSE, 1, 1, "unexpected byte 0x80"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const err_case *c = &cases[k];
        geom_diag d;
        geom_diag_clear(&d);
        geom_implicit_expr *e = (geom_implicit_expr *)1;
        geom_status st = geom_implicit_expr_compile(c->text, strlen(c->text), NULL, &e, &d);
        if (st != c->status || e != NULL || d.line != c->line || d.column != c->column ||
            !strstr(d.message, c->message) || d.status != st ||
            strcmp(d.source, "expression") != 0)
            fail_msg("'%s': status %d line %zu col %zu message '%s'; want %d %zu:%zu '%s'",
                     c->text, st, d.line, d.column, d.message, c->status, c->line, c->column,
                     c->message);
    }
    /* a NUL byte inside the given length */
    geom_diag d;
    geom_implicit_expr *e;
    assert_int_equal(geom_implicit_expr_compile("x +\0y", 5, NULL, &e, &d), GEOM_ERR_PARSE);
    assert_int_equal(d.column, 4);
    assert_non_null(strstr(d.message, "NUL"));
    /* the length bounds the text: "x + 1" read as "x +" */
    assert_int_equal(geom_implicit_expr_compile("x + 1", 3, NULL, &e, &d), GEOM_ERR_PARSE);
    /* invalid arguments */
    assert_int_equal(geom_implicit_expr_compile(NULL, 3, NULL, &e, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_implicit_expr_compile("x", 1, NULL, NULL, NULL), GEOM_ERR_INVALID_ARG);
    /* NULL diag is fine */
    assert_int_equal(geom_implicit_expr_compile("x +", 3, NULL, &e, NULL), GEOM_ERR_PARSE);
    assert_null(e);
}

static char *repeat(const char *a, size_t n, const char *mid, const char *b, size_t m)
{
    size_t la = strlen(a), lm = strlen(mid), lb = strlen(b);
    char *s = malloc(la * n + lm + lb * m + 1);
    assert_non_null(s);
    char *q = s;
    for (size_t i = 0; i < n; i++, q += la)
        memcpy(q, a, la);
    memcpy(q, mid, lm);
    q += lm;
    for (size_t i = 0; i < m; i++, q += lb)
        memcpy(q, b, lb);
    *q = '\0';
    return s;
}

static void test_limits(void **state)
{
    (void)state;
    geom_diag d;
    geom_implicit_expr *e;
    /* nesting: parentheses, unary minus, powers, calls */
    char *s = repeat("(", 100, "x", ")", 100);
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), NULL, &e, &d), GEOM_ERR_LIMIT);
    assert_non_null(strstr(d.message, "nested deeper than 64"));
    free(s);
    s = repeat("(", 60, "x", ")", 60);
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), NULL, &e, &d), GEOM_OK);
    geom_implicit_expr_destroy(e);
    free(s);
    s = repeat("-", 1000, "x", "", 0);
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), NULL, &e, &d), GEOM_ERR_LIMIT);
    assert_int_equal(d.column, 65);
    free(s);
    s = repeat("2^", 1000, "x", "", 0);
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), NULL, &e, &d), GEOM_ERR_LIMIT);
    free(s);
    /* the default length limit */
    s = repeat("-", 70000, "x", "", 0);
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), NULL, &e, &d), GEOM_ERR_LIMIT);
    assert_non_null(strstr(d.message, "longer than 65536"));
    free(s);
    s = repeat("sin(", 50000, "x", ")", 50000);
    geom_implicit_expr_options opt = {NULL, 1u << 20, 0};
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), &opt, &e, &d), GEOM_ERR_LIMIT);
    free(s);
    /* a raised depth limit, then the evaluation stack limit */
    opt.max_depth = 1000;
    s = repeat("1+(", 300, "x", ")", 300);
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), &opt, &e, &d), GEOM_OK);
    double p[3] = {1, 0, 0};
    assert_true(geom_implicit_expr_eval(e, p) == 301.0);
    geom_implicit_expr_destroy(e);
    free(s);
    s = repeat("x+(", 600, "x", ")", 600);
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), &opt, &e, &d), GEOM_ERR_LIMIT);
    assert_non_null(strstr(d.message, "stack"));
    free(s);
    /* a long flat expression needs neither depth nor stack */
    s = repeat("x+", 20000, "x", "", 0);
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), &opt, &e, &d), GEOM_OK);
    assert_true(geom_implicit_expr_eval(e, p) == 20001.0);
    double g[3];
    geom_implicit_expr_eval_grad(e, p, g);
    assert_true(g[0] == 20001.0);
    geom_implicit_expr_destroy(e);
    /* the length limit */
    opt.max_length = 10;
    assert_int_equal(geom_implicit_expr_compile(s, 11, &opt, &e, &d), GEOM_ERR_LIMIT);
    assert_int_equal(d.column, 11);
    assert_int_equal(geom_implicit_expr_compile(s, 10, &opt, &e, &d), GEOM_ERR_PARSE);
    free(s);
    s = repeat("1", 500, "", "", 0);
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), NULL, &e, &d), GEOM_ERR_LIMIT);
    free(s);
}

/* ---------------------------------------------------------- allocators */

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

static void test_allocator(void **state)
{
    (void)state;
    const char *text = "smooth_union(sphere(1), torus(2, 0.5), 0.3) + gyroid(2) * x * y * z"
                       " - min(x, y, z, 1, 2, 3) + max(sin(x), cos(y), tan(z))";
    for (size_t fail = 1; fail < 40; fail++) {
        counting c = {0, 0, fail};
        geom_allocator a = {c_alloc, c_realloc, c_free, &c};
        geom_implicit_expr_options opt = {&a, 0, 0};
        geom_implicit_expr *e = NULL;
        geom_status st = geom_implicit_expr_compile(text, strlen(text), &opt, &e, NULL);
        if (st == GEOM_OK) {
            assert_true(c.live > 0);
            geom_implicit_expr_destroy(e);
        } else {
            assert_int_equal(st, GEOM_ERR_NOMEM);
            assert_null(e);
        }
        assert_int_equal(c.live, 0);
    }
}

/* The batch evaluator gives bit-identical values to single evaluations. */
static void test_eval_many(void **state)
{
    (void)state;
    enum { N = 333 };
    double *p = malloc(3 * N * sizeof(double)), *out = malloc(N * sizeof(double));
    assert_non_null(p);
    assert_non_null(out);
    for (int i = 0; i < 3 * N; i++)
        p[i] = urange(-2.5, 2.5);
    p[0] = NAN;
    p[4] = INFINITY;
    for (size_t k = 0; k < sizeof interval_exprs / sizeof interval_exprs[0]; k++) {
        geom_implicit_expr *e = compile_ok(interval_exprs[k]);
        geom_implicit_expr_set_time(e, 0.25);
        geom_implicit_expr_eval_many(e, N, p, out);
        for (int i = 0; i < N; i++) {
            double v = geom_implicit_expr_eval(e, &p[3 * i]);
            if (!(memcmp(&v, &out[i], sizeof v) == 0 || (isnan(v) && isnan(out[i]))))
                fail_msg("%s at point %d: batch %.17g, single %.17g", interval_exprs[k], i,
                         out[i], v);
        }
        geom_implicit_expr_destroy(e);
    }
    /* a program deeper than the batch stack falls back to single points */
    char *s = repeat("x+(", 100, "x", ")", 100);
    geom_implicit_expr_options opt = {NULL, 0, 200};
    geom_implicit_expr *e;
    assert_int_equal(geom_implicit_expr_compile(s, strlen(s), &opt, &e, NULL), GEOM_OK);
    geom_implicit_expr_eval_many(e, N, p, out);
    for (int i = 1; i < N; i++)
        assert_true(out[i] == geom_implicit_expr_eval(e, &p[3 * i]));
    geom_implicit_expr_destroy(e);
    free(s);
    geom_implicit_expr_eval_many(NULL, 2, p, out);
    assert_true(isnan(out[0]) && isnan(out[1]));
    free(p);
    free(out);
}

/* The batched value-and-gradient path gives, bit for bit, what the single
 * dual-number evaluation gives (NaN where it gives NaN), on every
 * operation and primitive of the interval test set, and the value agrees
 * with geom_implicit_expr_eval. */
static bool same_or_nan(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0 || (isnan(a) && isnan(b));
}

static void test_eval_grad_many(void **state)
{
    (void)state;
    enum { N = 157 };
    double *p = malloc(3 * N * sizeof(double)), *val = malloc(N * sizeof(double));
    double *grd = malloc(3 * N * sizeof(double));
    assert_non_null(p);
    assert_non_null(val);
    assert_non_null(grd);
    for (int i = 0; i < 3 * N; i++)
        p[i] = urange(-2.5, 2.5);
    p[0] = NAN;
    p[4] = INFINITY;
    p[9] = p[10] = p[11] = 0.0; /* kinks of sqrt and abs at the origin */
    for (size_t k = 0; k < sizeof interval_exprs / sizeof interval_exprs[0]; k++) {
        geom_implicit_expr *e = compile_ok(interval_exprs[k]);
        geom_implicit_expr_set_time(e, 0.25);
        geom_implicit_expr_eval_grad_many(e, N, p, val, grd);
        for (int i = 0; i < N; i++) {
            double g[3];
            double v = geom_implicit_expr_eval_grad(e, &p[3 * i], g);
            if (!same_or_nan(v, val[i]) || !same_or_nan(g[0], grd[3 * i]) ||
                !same_or_nan(g[1], grd[3 * i + 1]) || !same_or_nan(g[2], grd[3 * i + 2]))
                fail_msg("%s at point %d: batch %.17g, single %.17g", interval_exprs[k], i,
                         val[i], v);
            assert_true(same_or_nan(v, geom_implicit_expr_eval(e, &p[3 * i])));
        }
        geom_implicit_expr_eval_grad_many(e, N, p, val, NULL); /* gradients not wanted */
        for (int i = 0; i < N; i++)
            assert_true(same_or_nan(val[i], geom_implicit_expr_eval(e, &p[3 * i])));
        geom_implicit_expr_destroy(e);
    }
    geom_implicit_expr_eval_grad_many(NULL, 2, p, val, grd);
    assert_true(isnan(val[0]) && isnan(val[1]) && isnan(grd[5]));
    free(p);
    free(val);
    free(grd);
}

static void test_field_adapter(void **state)
{
    (void)state;
    geom_implicit_expr *e = compile_ok("sphere(2)");
    geom_implicit_field f;
    geom_implicit_field_from_expr(e, &f);
    assert_true(f.exact);
    double p[3] = {3, 0, 0}, g[3];
    assert_true(f.value(f.user, p) == 1.0);
    assert_true(f.gradient(f.user, p, g) == 1.0);
    assert_true(g[0] == 1.0 && g[1] == 0.0 && g[2] == 0.0);
    geom_implicit_expr_destroy(e);
    geom_implicit_expr_destroy(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_arithmetic),
        cmocka_unit_test(test_constant_folding),
        cmocka_unit_test(test_primitives),
        cmocka_unit_test(test_nonfinite),
        cmocka_unit_test(test_gradient_analytic),
        cmocka_unit_test(test_gradient_richardson),
        cmocka_unit_test(test_interval_enclosure),
        cmocka_unit_test(test_interval_cases),
        cmocka_unit_test(test_syntax_errors),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_allocator),
        cmocka_unit_test(test_eval_many),
        cmocka_unit_test(test_eval_grad_many),
        cmocka_unit_test(test_field_adapter),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
