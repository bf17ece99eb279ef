/*
 * ray, stiff and extreme cases: rays tangent to spheres at relative
 * distances 1e-1..1e-12 from tangency (hit/miss by the exact line distance),
 * a fan of 2000 sliver triangles hit exactly once through its apex and
 * spokes, a NURBS sphere of radius 1e-3 at 1e7, a torus moved to 1e7 by a
 * transform, a flush CSG difference (coincident faces give no slivers), and
 * rays starting on a surface.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/ray.h"
#include "unit/ray_testutil.h" /* mkray */

static size_t all(const geom_ray_scene *s, geom_ray r, geom_ray_hit *h, size_t cap)
{
    size_t n = 0;
    assert_int_equal(geom_ray_scene_all(s, &r, h, cap, &n), GEOM_OK);
    return n;
}

static void test_sphere_tangent(void **state)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double c[3] = {0.125, -3, 7};
    geom_ray_hit h[4];
    int k;
    (void)state;
    geom_ray_scene_add_sphere(s, c, 2, NULL);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    for (k = 1; k <= 12; k++) {
        double e = pow(10.0, -k);
        /* lines at distance 2 (1 -+ e) from the centre, along x */
        assert_int_equal(all(s, mkray(-10, -3 + 2 * (1 - e), 7, 1, 0, 0), h, 4), 2);
        assert_int_equal(all(s, mkray(-10, -3 + 2 * (1 + e), 7, 1, 0, 0), h, 4), 0);
    }
    geom_ray_scene_destroy(s);
}

static void test_sliver_fan(void **state)
{
    const size_t n = 2000;
    double *p = malloc((n + 1) * 3 * sizeof(double));
    uint32_t *t = malloc(n * 3 * sizeof(uint32_t));
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray_hit h[8];
    size_t i, bad = 0;
    (void)state;
    p[0] = 0.1;
    p[1] = 0.2;
    p[2] = 0.3; /* apex, slightly raised: a shallow cone */
    for (i = 0; i < n; i++) {
        double a = 2 * 3.14159265358979323846 * (double)i / (double)n;
        p[3 * (i + 1)] = cos(a);
        p[3 * (i + 1) + 1] = sin(a);
        p[3 * (i + 1) + 2] = 0;
        t[3 * i] = 0;
        t[3 * i + 1] = (uint32_t)(i + 1);
        t[3 * i + 2] = (uint32_t)((i + 1) % n + 1);
    }
    geom_ray_scene_add_triangles(s, p, n + 1, t, n, NULL, NULL);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    /* through the apex from many directions below */
    for (i = 0; i < 200; i++) {
        double a = 0.7 * (double)i, dx = 0.3 * cos(a), dy = 0.3 * sin(a);
        geom_ray r = mkray(0.1 - dx, 0.2 - dy, -0.7, dx, dy, 1);
        if (all(s, r, h, 8) != 1) bad++;
    }
    /* through points on the spokes (midpoints of the shared edges) */
    for (i = 0; i < n; i += 7) {
        const double *q = p + 3 * (i + 1);
        double m[3] = {0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])};
        geom_ray r = mkray(m[0] * 0.3, m[1] * 0.3, -1, m[0] * 0.7, m[1] * 0.7, m[2] + 1);
        if (all(s, r, h, 8) != 1) bad++;
    }
    assert_int_equal(bad, 0);
    geom_ray_scene_destroy(s);
    free(p);
    free(t);
}

static void test_far_small(void **state)
{
    geom_surface_frame fr;
    double ku[16], kv[16], pts[3 * 64], w[64];
    geom_nurbs_surface sph;
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray_hit h[8];
    double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1e7, -1e7, 1e7, 1};
    uint32_t tor;
    size_t n;
    (void)state;
    memset(&fr, 0, sizeof fr);
    fr.center[0] = 1e7;
    fr.center[1] = 1e7;
    fr.center[2] = 1e7;
    fr.xaxis[0] = 1;
    fr.zaxis[2] = 1;
    assert_int_equal(geom_surface_sphere(&fr, 1e-3, ku, kv, pts, w, &sph), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_surface(s, &sph, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_torus(s, 2e-3, 1e-3, &tor), GEOM_OK);
    assert_int_equal(geom_ray_scene_set_transform(s, tor, m), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    n = all(s, mkray(1e7 + 5e-4, 1e7, 1e7 - 1, 0, 0, 1), h, 8);
    assert_int_equal(n, 2);
    {
        double dz = sqrt(1e-6 - 25e-8);
        print_message("far small sphere: t errors %.3g %.3g (t_error %.3g)\n", h[0].t - (1 - dz), h[1].t - (1 + dz), h[0].t_error);
        assert_true(fabs(h[0].t - (1 - dz)) < 1e-8 && fabs(h[0].t - (1 - dz)) <= h[0].t_error);
        assert_true(fabs(h[1].t - (1 + dz)) < 1e-8);
        assert_true(h[0].enter && !h[1].enter);
    }
    n = all(s, mkray(1e7 - 1, -1e7, 1e7, 1, 0, 0), h, 8);
    assert_int_equal(n, 4);
    assert_true(fabs(h[0].t - (1 - 3e-3)) < 1e-9 && fabs(h[3].t - (1 + 3e-3)) < 1e-9);
    geom_ray_scene_destroy(s);
}

static void test_flush_csg(void **state)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double a0[3] = {0, 0, 0}, a1[3] = {2, 2, 2}, b0[3] = {1, 0, 0}, b1[3] = {2, 2, 2};
    uint32_t a, b;
    geom_ray_hit h[8];
    size_t n;
    (void)state;
    geom_ray_scene_add_box(s, a0, a1, &a);
    geom_ray_scene_add_box(s, b0, b1, &b); /* shares faces with a */
    geom_ray_scene_add_csg(s, GEOM_RAY_CSG_DIFFERENCE, a, b, NULL);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    n = all(s, mkray(-1, 1, 1, 1, 0, 0), h, 8);
    assert_int_equal(n, 2);
    assert_true(h[0].t == 1 && h[0].enter && h[1].t == 2 && !h[1].enter);
    assert_true(h[1].ng.x == 1); /* the cut face: b's -x face reversed, outward of a - b */
    /* along the coincident face y = 2 inside the remaining part: no zero-length slivers */
    n = all(s, mkray(0.5, 1, -1, 0, 0, 1), h, 8);
    assert_int_equal(n, 2);
    geom_ray_scene_destroy(s);
}

static void test_start_on_surface(void **state)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double c[3] = {0, 0, 0};
    geom_ray_hit h[4], hc;
    int found;
    geom_ray r;
    (void)state;
    geom_ray_scene_add_sphere(s, c, 1, NULL);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    /* from the surface inward: the far side at t = 2 (and possibly t = 0) */
    r = mkray(1, 0, 0, -1, 0, 0);
    assert_int_equal(geom_ray_scene_closest(s, &r, &hc, &found), GEOM_OK);
    assert_true(found);
    assert_true(hc.t == 0 || fabs(hc.t - 2) < 1e-15);
    /* with the offset helper: exactly the far side */
    {
        geom_vec3 o = geom_ray_offset_origin(&hc, r.dir);
        geom_ray r2 = mkray(o.x, o.y, o.z, -1, 0, 0);
        size_t n = all(s, r2, h, 4);
        (void)n;
        assert_true(h[n - 1].t > 1.9);
    }
    geom_ray_scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_tangent), cmocka_unit_test(test_sliver_fan),
        cmocka_unit_test(test_far_small),      cmocka_unit_test(test_flush_csg),
        cmocka_unit_test(test_start_on_surface),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
