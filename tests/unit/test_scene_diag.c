/*
 * A public function that fails with a geom_diag given fills it: the status
 * it returns, and a message (so that no caller can print "invalid argument:
 * ok" from an empty diagnostic). The calls below are the bad-argument paths
 * that used to return a bare status.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "geom/geom.h"

static void expect_filled(geom_status st, const geom_diag *d)
{
    assert_true(st < 0);
    assert_int_equal(d->status, st);
    assert_true(d->message[0] != '\0');
    char buf[600];
    geom_diag_format(d, buf, sizeof buf);
    assert_null(strstr(buf, ": ok"));
}

static void test_bad_arguments_fill_the_diag(void **state)
{
    (void)state;
    geom_diag d;
    uint32_t id;
    memset(&d, 0, sizeof d);
    expect_filled(geom_ray_scene_add_surface(NULL, NULL, &id, &d), &d);
    memset(&d, 0, sizeof d);
    expect_filled(geom_ray_scene_add_subdiv(NULL, NULL, 0, 1, &id, &d), &d);
    memset(&d, 0, sizeof d);
    expect_filled(geom_ray_scene_build(NULL, NULL, NULL, &d), &d);
    memset(&d, 0, sizeof d);
    geom_scene_shapes *sh = NULL;
    expect_filled(geom_scene_shapes_from_ray(NULL, &sh, &d), &d);
    memset(&d, 0, sizeof d);
    size_t n = 0;
    expect_filled(geom_scene_shape_to_ray(NULL, NULL, &id, &n, &d), &d);
    memset(&d, 0, sizeof d);
    geom_subdiv_refiner *r = NULL;
    expect_filled(geom_subdiv_refiner_create(NULL, NULL, &r, &d), &d);
    memset(&d, 0, sizeof d);
    expect_filled(geom_subdiv_refiner_create_soup(3, 1, NULL, NULL, NULL, &r, &d), &d);
    memset(&d, 0, sizeof d);
    geom_mesh *m = NULL;
    expect_filled(geom_subdiv_mesh(NULL, NULL, 1, 0, &m, NULL, &d), &d);
    memset(&d, 0, sizeof d);
    expect_filled(geom_subdiv_build_mesh(NULL, 0, NULL, NULL, NULL, &m, NULL, &d), &d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_arguments_fill_the_diag),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
