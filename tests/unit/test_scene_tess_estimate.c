/*
 * geom_scene_tessellate_estimate for shapes made by marching cubes
 * (quadrics, implicit expressions, volumes, CSG): an upper bound of the
 * triangles geom_scene_tessellate makes, and a tight one: made <= estimate
 * <= 1.5 made, on a sphere and a torus as expressions, a gyroid, a capped
 * cylinder quadric, a CSG difference (sharp edges: the refinement passes
 * run), a sampled volume, at tolerances from 1e-1 to 1e-3 of the size.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <time.h>
#include <string.h>

#include "unit/scene_testutil.h"

static double worst = 0, best = 1e300;
/* the cheap bound (geom_scene_export_estimate with max_triangles): its
 * range over made and its largest cost relative to the tessellation */
static double cheap_worst = 0, cheap_best = 1e300, cheap_cost = 0;

/* geom_scene_export_estimate of s alone at tol, cheap (max_triangles
 * large) or exact (max_triangles 0). */
static double export_estimate(const geom_shape *s, double tol, double max_triangles)
{
    geom_material mat;
    memset(&mat, 0, sizeof mat);
    geom_scene_object obj = {s, 0};
    geom_export_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = tol;
    o.max_triangles = max_triangles;
    double t = -1;
    assert_int_equal(geom_scene_export_estimate(NULL, &mat, 1, &obj, 1, &o, NULL, &t, NULL),
                     GEOM_OK);
    return t;
}

static void check(const geom_shape *s, double tol)
{
    geom_tess_request rq;
    memset(&rq, 0, sizeof rq);
    rq.tol = tol;
    rq.attributes = GEOM_NEEDS_NORMAL;
    rq.extent.min = geom_vec3_make(-3, -3, -3);
    rq.extent.max = geom_vec3_make(3, 3, 3);
    double est = -1;
    double c0 = (double)clock();
    assert_int_equal(geom_scene_tessellate_estimate(s, &rq, &est), GEOM_OK);
    double c1 = (double)clock();
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_scene_tessellate(s, &rq, m, NULL, NULL), GEOM_OK);
    double c2 = (double)clock();
    double made = (double)tri_count(m);
    geom_mesh_destroy(m);
    double c3 = (double)clock();
    double cheap = export_estimate(s, tol, 1e15);
    double c4 = (double)clock();
    /* max_triangles below the cheap bound: the exact trials' answer */
    assert_true(export_estimate(s, tol, 0.5 * cheap) == est);
    assert_true(export_estimate(s, tol, 0) == est);
    double cost = (c4 - c3) / fmax(c2 - c1, 1.0);
    print_message("%-10s tol %-6g cheap bound %10.0f ratio %.3f (CPU %.4f s, %.3f of the "
                  "tessellation's)\n",
                  s->name, tol, cheap, cheap / made, (c4 - c3) / CLOCKS_PER_SEC, cost);
    if (cheap / made > cheap_worst)
        cheap_worst = cheap / made;
    if (cheap / made < cheap_best)
        cheap_best = cheap / made;
    /* the cost over tessellations of at least 20 ms (clock()'s resolution) */
    if ((c2 - c1) / CLOCKS_PER_SEC >= 0.02 && cost > cheap_cost)
        cheap_cost = cost;
    if (!(cheap >= made))
        fail_msg("%s tol %g: cheap bound %g below made %g", s->name, tol, cheap, made);
    print_message("%-10s tol %-6g made %8.0f estimate %10.0f ratio %.3f (CPU: estimate %.3f s, "
                  "tessellate %.3f s)\n",
                  s->name, tol, made, est, est / made, (c1 - c0) / CLOCKS_PER_SEC,
                  (c2 - c1) / CLOCKS_PER_SEC);
    if (est / made > worst)
        worst = est / made;
    if (est / made < best)
        best = est / made;
    if (!(est >= made && est <= 1.5 * made))
        fail_msg("%s tol %g: estimate %g, made %g (expected made .. 1.5 made)", s->name, tol, est, made);
}

static void test_implicit_shapes(void **state)
{
    (void)state;
    static const struct {
        const char *name, *expr;
        double b[6];
    } ex[] = {
        {"sphere", "sqrt(x*x + y*y + z*z) - 1", {-1.2, -1.2, -1.2, 1.2, 1.2, 1.2}},
        {"torus", "torus(1, 0.3)", {-1.5, -1.5, -0.5, 1.5, 1.5, 0.5}},
        {"gyroid", "sin(x)*cos(y) + sin(y)*cos(z) + sin(z)*cos(x)", {-3, -3, -3, 3, 3, 3}},
    };
    for (size_t k = 0; k < sizeof ex / sizeof ex[0]; k++) {
        geom_implicit_expr *e = NULL;
        assert_int_equal(geom_implicit_expr_compile(ex[k].expr, strlen(ex[k].expr), NULL, &e, NULL),
                         GEOM_OK);
        geom_shape s;
        memset(&s, 0, sizeof s);
        s.kind = GEOM_SHAPE_IMPLICIT;
        s.name = ex[k].name;
        s.expr = e;
        memcpy(s.bounds, ex[k].b, sizeof s.bounds);
        for (double tol = 1e-1; tol >= 0.99e-3; tol /= 10)
            check(&s, tol);
        geom_implicit_expr_destroy(e);
    }
    /* a capped cylinder (quadric x^2 + y^2 - 0.5^2 clipped to |z| <= 1) */
    static const double clip[6] = {-1, -1, -1, 1, 1, 1};
    geom_shape q;
    memset(&q, 0, sizeof q);
    q.kind = GEOM_SHAPE_QUADRIC;
    q.name = "cylinder";
    q.q[0] = q.q[1] = 1;
    q.q[9] = -0.25;
    q.clip = clip;
    q.capped = 1;
    for (double tol = 1e-1; tol >= 0.99e-3; tol /= 10)
        check(&q, tol);
    /* box minus ball: sharp edges keep the error above tol, so every
     * refinement pass runs */
    geom_shape box, ball, cut;
    memset(&box, 0, sizeof box);
    box.kind = GEOM_SHAPE_BOX;
    box.min[0] = box.min[1] = box.min[2] = -1;
    box.max[0] = box.max[1] = box.max[2] = 1;
    memset(&ball, 0, sizeof ball);
    ball.kind = GEOM_SHAPE_SPHERE;
    ball.p[2] = 1;
    ball.radius = 0.8;
    memset(&cut, 0, sizeof cut);
    cut.kind = GEOM_SHAPE_CSG;
    cut.name = "csg";
    cut.csg_op = 3;
    cut.a = &box;
    cut.b = &ball;
    for (double tol = 1e-1; tol >= 0.99e-3; tol /= 10)
        check(&cut, tol);
    /* a sampled volume: 1 - |p|^2 on a 17^3 grid over [-2, 2]^3, inside above */
    geom_implicit_grid g;
    memset(&g, 0, sizeof g);
    g.dims[0] = g.dims[1] = g.dims[2] = 17;
    g.type = GEOM_IMPLICIT_SCALAR_F64;
    g.spacing[0] = g.spacing[1] = g.spacing[2] = 0.25;
    g.origin[0] = g.origin[1] = g.origin[2] = -2;
    geom_implicit_volume *v = NULL;
    assert_int_equal(geom_implicit_volume_create(&g, NULL, &v), GEOM_OK);
    double *d = geom_implicit_volume_data(v);
    for (int k = 0; k < 17; k++)
        for (int j = 0; j < 17; j++)
            for (int i = 0; i < 17; i++) {
                double x = -2 + 0.25 * i, y = -2 + 0.25 * j, z = -2 + 0.25 * k;
                d[i + 17 * (j + 17 * k)] = 1 - (x * x + y * y + z * z);
            }
    geom_shape vs;
    memset(&vs, 0, sizeof vs);
    vs.kind = GEOM_SHAPE_VOLUME;
    vs.name = "volume";
    vs.volume = v;
    vs.inside = 1;
    for (double tol = 1e-1; tol >= 0.99e-3; tol /= 10)
        check(&vs, tol);
    geom_implicit_volume_destroy(v);
    print_message("estimate / made: %.3f .. %.3f\n", best, worst);
    print_message("cheap bound / made: %.3f .. %.3f, its CPU at most %.3f of the tessellation's\n",
                  cheap_best, cheap_worst, cheap_cost);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_implicit_shapes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
