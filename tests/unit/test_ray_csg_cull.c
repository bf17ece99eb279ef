/*
 * ray CSG early outs against closed forms: a child whose bounding box the
 * line misses is skipped (union, intersection, difference each give what
 * the other child alone or nothing gives), a bounded child's hits beyond
 * tmax are not needed (the result before tmax is unchanged), and an
 * unbounded child (a half-space plane) that the line leaves after tmax still
 * decides the inside state before it.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "geom/ray.h"
#include "unit/ray_testutil.h"

/* big sphere r=1 at the origin op small sphere r=0.25 at (0, 0, 2) (b) */
static geom_ray_scene *two_spheres(geom_ray_csg_op op)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double c0[3] = {0, 0, 0}, c1[3] = {0, 0, 2};
    uint32_t a, b, id;
    assert_int_equal(geom_ray_scene_add_sphere(s, c0, 1, &a), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_sphere(s, c1, 0.25, &b), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_csg(s, op, a, b, &id), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    return s;
}

static void closest(const geom_ray_scene *s, geom_ray r, int want, double t, double nz)
{
    geom_ray_hit h;
    int found = -1;
    assert_int_equal(geom_ray_scene_closest(s, &r, &h, &found), GEOM_OK);
    assert_int_equal(found, want);
    if (want) {
        assert_true(fabs(h.t - t) < 1e-12);
        assert_true(fabs(h.ng.z - nz) < 1e-12);
    }
}

static void test_missed_child(void **state)
{
    (void)state;
    /* a ray along x at height 0.6 misses the small sphere's box (z in [1.75, 2.25]) */
    double x = sqrt(1 - 0.36);
    geom_ray r = mkray(-5, 0, 0.6, 1, 0, 0);
    geom_ray_scene *s = two_spheres(GEOM_RAY_CSG_UNION);
    closest(s, r, 1, 5 - x, 0.6);
    geom_ray_scene_destroy(s);
    s = two_spheres(GEOM_RAY_CSG_DIFFERENCE);
    closest(s, r, 1, 5 - x, 0.6);
    geom_ray_hit hits[4];
    size_t n = 0;
    assert_int_equal(geom_ray_scene_all(s, &r, hits, 4, &n), GEOM_OK);
    assert_int_equal(n, 2);
    assert_true(fabs(hits[1].t - (5 + x)) < 1e-12 && !hits[1].enter);
    geom_ray_scene_destroy(s);
    s = two_spheres(GEOM_RAY_CSG_INTERSECTION);
    closest(s, r, 0, 0, 0);
    geom_ray_scene_destroy(s);
    /* down the z axis both children are met (disjoint): the difference
     * starts at the big sphere's top, the union at the small one's */
    s = two_spheres(GEOM_RAY_CSG_DIFFERENCE);
    closest(s, mkray(0, 0, 5, 0, 0, -1), 1, 4, 1);
    geom_ray_scene_destroy(s);
    s = two_spheres(GEOM_RAY_CSG_UNION);
    closest(s, mkray(0, 0, 5, 0, 0, -1), 1, 2.75, 1);
    /* the same with tmax before the big sphere: the small one only */
    closest(s, mkray_to(0, 0, 5, 0, 0, -1, 3.5), 1, 2.75, 1);
    /* tmax between the small sphere's two hits, from inside it */
    closest(s, mkray_to(0, 0, 2, 0, 0, -1, 0.2), 0, 0, 0);
    closest(s, mkray_to(0, 0, 2, 0, 0, -1, 0.3), 1, 0.25, -1);
    geom_ray_scene_destroy(s);
}

static void test_halfspace_after_tmax(void **state)
{
    (void)state;
    /* box [-1,1]^3 minus the half-space z < 0 (plane through 0, normal +z):
     * the upper half of the box. A ray going up from z = -5 is inside the
     * half-space until z = 0, so the box's face at z = -1 is cut away; the
     * first hit is the cut face z = 0 (normal reversed: -z) at t = 5. */
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double mn[3] = {-1, -1, -1}, mx[3] = {1, 1, 1}, p[3] = {0, 0, 0}, nrm[3] = {0, 0, 1};
    uint32_t a, b, id;
    assert_int_equal(geom_ray_scene_add_box(s, mn, mx, &a), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_plane(s, p, nrm, &b), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_csg(s, GEOM_RAY_CSG_DIFFERENCE, a, b, &id), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    closest(s, mkray(0.2, 0.3, -5, 0, 0, 1), 1, 5, -1);
    /* tmax before the plane (z = -0.5): the box's bottom face at z = -1 is
     * inside the half-space, so nothing is hit although the plane's own
     * crossing lies beyond tmax */
    closest(s, mkray_to(0.2, 0.3, -5, 0, 0, 1, 4.5), 0, 0, 0);
    int found = -1;
    geom_ray r = mkray_to(0.2, 0.3, -5, 0, 0, 1, 4.5);
    assert_int_equal(geom_ray_scene_any(s, &r, &found), GEOM_OK);
    assert_int_equal(found, 0);
    /* from above: the top face */
    closest(s, mkray(0.2, 0.3, 5, 0, 0, -1), 1, 4, 1);
    geom_ray_scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_missed_child),
        cmocka_unit_test(test_halfspace_after_tmax),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
