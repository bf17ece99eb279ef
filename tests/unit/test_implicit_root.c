/* geom_implicit_bracket_root, the one root finder of marching squares and
 * marching cubes' refinement, against closed forms. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>

#include "geom/implicit.h"

static double sq2(void *u, double x)
{
    (void)u;
    return x * x - 2.0;
}

static double step(void *u, double x)
{
    (void)u;
    return x < 0.3 ? -1.0 : 1.0;
}

static double nan_above(void *u, double x)
{
    (void)u;
    return x > 0.25 ? NAN : x - 0.75;
}

static double cubic(void *u, double x)
{
    double c = *(const double *)u;
    return (x - c) * (x - c) * (x - c);
}

static void test_bracket_root(void **state)
{
    (void)state;
    size_t ev = 0;
    /* smooth: the root to the last bit (the bracket ends adjacent doubles) */
    double r = geom_implicit_bracket_root(sq2, NULL, 1.0, 2.0, -1.0, 2.0, 1.3, 100, &ev);
    assert_true(fabs(r - sqrt(2.0)) <= 2 * DBL_EPSILON);
    assert_true(ev > 0 && ev < 100);
    /* a jump: a point next to it, strictly inside */
    r = geom_implicit_bracket_root(step, NULL, 0.0, 1.0, -1.0, 1.0, 0.5, 200, NULL);
    assert_true(fabs(r - 0.3) <= 2 * DBL_EPSILON);
    /* a triple root (slow for regula falsi: the bisection safeguard) */
    double c = 0.123456789;
    ev = 0;
    r = geom_implicit_bracket_root(cubic, &c, 0.0, 1.0, cubic(&c, 0.0), cubic(&c, 1.0), 0.5, 200,
                                   &ev);
    assert_true(fabs(r - c) <= 1e-5); /* f is flat: |f| < 1e-15 within 1e-5 */
    assert_true(ev <= 200);
    /* NaN stops the search; the result stays strictly inside */
    r = geom_implicit_bracket_root(nan_above, NULL, 0.0, 1.0, -0.75, 1.0, 0.5, 50, NULL);
    assert_true(r > 0.0 && r < 1.0);
    /* no iterations: the start point, or the midpoint when it is not inside */
    assert_true(geom_implicit_bracket_root(sq2, NULL, 1.0, 2.0, -1.0, 2.0, 1.3, 0, NULL) == 1.3);
    assert_true(geom_implicit_bracket_root(sq2, NULL, 1.0, 2.0, -1.0, 2.0, 5.0, 0, NULL) == 1.5);
    assert_true(geom_implicit_bracket_root(sq2, NULL, 1.0, 2.0, -1.0, 2.0, 1.3, 1, NULL) > 1.0);
    assert_true(geom_implicit_bracket_root(NULL, NULL, 1.0, 2.0, -1.0, 2.0, 1.3, 10, NULL) == 1.3);
    assert_true(geom_implicit_bracket_root(sq2, NULL, 2.0, 1.0, -1.0, 2.0, 1.3, 10, NULL) == 1.3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bracket_root),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
