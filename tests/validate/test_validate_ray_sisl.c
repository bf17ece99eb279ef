/*
 * ray on B-spline and NURBS surfaces against SISL's line/surface
 * intersection (s1856): on a wavy bicubic B-spline patch (several hits per
 * ray) and a rational biquadratic patch, every ray's hit set from
 * geom_ray_scene_all equals SISL's intersection points (same count, (u, v)
 * within 1e-7 of the domain, points on the line).
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

#include "geom/ray.h"
#include "geom_validate_sisl.h"

static uint64_t rng = 0x853c49e6748fea9bull;
static double urand(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) * 0x1p-53;
}

static void compare(const geom_nurbs_surface *s, int nrays, double amp)
{
    gv_sisl_surface *ss = gv_sisl_surface_create(s->degree_u, s->degree_v, s->nu, s->nv, s->knots_u,
                                                  s->knots_v, s->points, s->weights);
    geom_ray_scene *sc = geom_ray_scene_create(NULL);
    int i, compared = 0, multi = 0;
    assert_non_null(ss);
    assert_int_equal(geom_ray_scene_add_surface(sc, s, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(sc, NULL, NULL, NULL), GEOM_OK);
    for (i = 0; i < nrays; i++) {
        double o[3] = {urand() * 3, urand() * 3, 2 + amp}, d[3] = {urand() - 0.5, urand() - 0.5, -1};
        double par[64];
        size_t ns = 0, ng = 0, k, j;
        geom_ray r;
        geom_ray_hit h[32];
        /* grazing rays for some */
        if (i % 3 == 0) {
            d[2] = -0.15 * urand();
            o[2] = amp * 0.5 * urand();
            o[0] = -1;
            d[0] = 1;
        }
        if (gv_sisl_line_surface(ss, o, d, 1e-12, par, 32, &ns) != GV_SISL_OK) continue;
        r.origin = geom_vec3_make(o[0], o[1], o[2]);
        r.dir = geom_vec3_make(d[0], d[1], d[2]);
        r.tmin = -INFINITY;
        r.tmax = INFINITY;
        assert_int_equal(geom_ray_scene_all(sc, &r, h, 32, &ng), GEOM_OK);
        if (ns != ng) {
            print_message("ray %d: SISL %zu points, libgeom %zu\n", i, ns, ng);
            for (k = 0; k < ns; k++) print_message("  sisl %.17g %.17g\n", par[2 * k], par[2 * k + 1]);
            for (k = 0; k < ng; k++) print_message("  geom %.17g %.17g t %.17g\n", h[k].u, h[k].v, h[k].t);
        }
        assert_int_equal(ns, ng);
        for (k = 0; k < ns; k++) {
            int ok = 0;
            for (j = 0; j < ng; j++)
                if (fabs(h[j].u - par[2 * k]) < 1e-7 && fabs(h[j].v - par[2 * k + 1]) < 1e-7) ok = 1;
            assert_true(ok);
        }
        compared++;
        multi += ns > 1;
    }
    print_message("%d rays compared with s1856, %d with several hits\n", compared, multi);
    assert_true(compared > nrays / 2);
    geom_ray_scene_destroy(sc);
    gv_sisl_surface_destroy(ss);
}

static void test_wavy_bspline(void **state)
{
    enum { N = 7, P = 3 };
    double ku[N + P + 1] = {0, 0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1, 1}, pts[3 * N * N];
    geom_nurbs_surface s;
    int i, j;
    (void)state;
    for (i = 0; i < N; i++)
        for (j = 0; j < N; j++) {
            pts[3 * (i * N + j)] = 3.0 * i / (N - 1);
            pts[3 * (i * N + j) + 1] = 3.0 * j / (N - 1);
            pts[3 * (i * N + j) + 2] = 0.8 * sin(2.1 * i) * cos(1.7 * j);
        }
    s.degree_u = s.degree_v = P;
    s.nu = s.nv = N;
    s.knots_u = s.knots_v = ku;
    s.points = pts;
    s.weights = NULL;
    compare(&s, 300, 0.8);
}

static void test_rational(void **state)
{
    double ku[6] = {0, 0, 0, 1, 1, 1}, pts[27], w[9];
    geom_nurbs_surface s;
    int i, j;
    (void)state;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            pts[3 * (i * 3 + j)] = 1.5 * i;
            pts[3 * (i * 3 + j) + 1] = 1.5 * j;
            pts[3 * (i * 3 + j) + 2] = (i == 1 && j == 1) ? 1.5 : (i == 1 || j == 1) ? -0.5 : 0.2;
            w[i * 3 + j] = (i == 1 && j == 1) ? 3.0 : (i == 1 || j == 1) ? 0.6 : 1.0;
        }
    s.degree_u = s.degree_v = 2;
    s.nu = s.nv = 3;
    s.knots_u = s.knots_v = ku;
    s.points = pts;
    s.weights = w;
    compare(&s, 300, 1.5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wavy_bspline),
        cmocka_unit_test(test_rational),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
