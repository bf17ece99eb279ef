/*
 * Surfaces of the tessellation benchmark (bench_tessellate.c) that the
 * tessellation tests use as well.
 *
 *  tess_load_teapot    Newell's teapot (DIR/teapot.bpt, 32 bicubic patches)
 *  tess_test_teapot    the same from $GEOM_TEST_DATA for the cmocka tests
 *                      (defined when <cmocka.h> is included first)
 */
#ifndef GEOM_TESTS_TESS_SHAPES_H
#define GEOM_TESTS_TESS_SHAPES_H

#include <stdio.h>
#include <stdlib.h>

#include "geom/surface.h"

/* NULL with the reason in *d if DIR/teapot.bpt cannot be read. */
static inline geom_surface_set *tess_load_teapot(const char *dir, geom_diag *d)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/teapot.bpt", dir ? dir : "data");
    geom_surface_set *set = NULL;
    if (geom_surface_read_bpt(path, NULL, &set, d) != GEOM_OK)
        return NULL;
    return set;
}

#ifdef fail_msg
/* The teapot of $GEOM_TEST_DATA; the cmocka test fails if it cannot be read. */
static inline geom_surface_set *tess_test_teapot(void)
{
    geom_diag d;
    geom_surface_set *set = tess_load_teapot(getenv("GEOM_TEST_DATA"), &d);
    if (!set)
        fail_msg("cannot read the teapot: %s", d.message);
    return set;
}
#endif

#endif
