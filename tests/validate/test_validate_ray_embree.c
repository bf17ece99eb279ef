/*
 * ray against Embree 3 (default and robust mode, one thread): the same
 * hit/miss on every ray of dense camera grids on a smooth and a bumpy closed
 * mesh, t within float accuracy; Embree-style watertightness tests (rays
 * from inside the closed bumpy mesh exactly through its vertices and edge
 * midpoints: no leak and no double hit in libgeom, leaks of both Embree
 * modes reported); NaN/Inf rays give a status and no hit.
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
#include "geom_validate_embree.h"
#include "unit/ray_testutil.h"

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double urand(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) * 0x1p-53;
}

static tmesh bumpy(int levels)
{
    tmesh m = icosphere(levels);
    size_t i;
    for (i = 0; i < m.nv; i++) {
        double *p = m.p + 3 * i, s = 1 + 0.15 * sin(7 * p[0]) * cos(5 * p[1]) + 0.05 * urand();
        p[0] = p[0] * s + 3;
        p[1] = p[1] * s - 2;
        p[2] = p[2] * s + 1;
    }
    return m;
}

static geom_ray_scene *scene_of(const tmesh *m)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    assert_int_equal(geom_ray_scene_add_triangles(s, m->p, m->nv, m->t, m->nt, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    return s;
}

static void camera_grid(const tmesh *m, int robust)
{
    const int N = 200;
    size_t nr = (size_t)N * N, i, differ = 0, hits = 0;
    double *rays = malloc(nr * 6 * sizeof(double)), *te = malloc(nr * sizeof(double)), maxrel = 0;
    double c[3] = {0, 0, 0};
    geom_ray_scene *s = scene_of(m);
    for (i = 0; i < m->nv; i++) {
        c[0] += m->p[3 * i] / (double)m->nv;
        c[1] += m->p[3 * i + 1] / (double)m->nv;
        c[2] += m->p[3 * i + 2] / (double)m->nv;
    }
    for (i = 0; i < nr; i++) {
        double sx = ((double)(i % N) + 0.5) / N * 2 - 1, sy = ((double)(i / N) + 0.5) / N * 2 - 1;
        double *r = rays + 6 * i;
        r[0] = c[0] + 0.7;
        r[1] = c[1] + 0.3;
        r[2] = c[2] + 5;
        r[3] = -0.7 + 1.6 * sx;
        r[4] = -0.3 + 1.6 * sy;
        r[5] = -5;
    }
    assert_int_equal(gv_embree_closest(m->p, m->nv, m->t, m->nt, robust, rays, nr, te, NULL), 0);
    for (i = 0; i < nr; i++) {
        const double *q = rays + 6 * i;
        geom_ray r;
        geom_ray_hit h;
        int found = 0;
        r.origin = geom_vec3_make(q[0], q[1], q[2]);
        r.dir = geom_vec3_make(q[3], q[4], q[5]);
        r.tmin = 0;
        r.tmax = INFINITY;
        assert_int_equal(geom_ray_scene_closest(s, &r, &h, &found), GEOM_OK);
        if (found != !isnan(te[i])) {
            differ++;
            continue;
        }
        if (found) {
            double rel = fabs(h.t - te[i]) / te[i];
            hits++;
            if (rel > maxrel) maxrel = rel;
        }
    }
    printf("embree %s: %zu rays, %zu hits, %zu differ in hit/miss, max |t - t_embree|/t = %.3g\n",
           robust ? "robust" : "default", nr, hits, differ, maxrel);
    assert_int_equal(differ, 0);
    assert_true(hits > nr / 10);
    assert_true(maxrel < 1e-5); /* float accuracy of Embree's t (inputs rounded to float) */
    geom_ray_scene_destroy(s);
    free(rays);
    free(te);
}

static void test_camera_smooth(void **state)
{
    tmesh m = icosphere(4);
    (void)state;
    camera_grid(&m, 0);
    camera_grid(&m, 1);
    free(m.p);
    free(m.t);
}

static void test_camera_bumpy(void **state)
{
    tmesh m = bumpy(4);
    (void)state;
    camera_grid(&m, 0);
    camera_grid(&m, 1);
    free(m.p);
    free(m.t);
}

/* Embree's watertightness test: rays from inside aimed exactly at every
 * vertex and edge midpoint. libgeom must find exactly one hit each (closest
 * and all-hits); Embree's misses are reported for comparison. */
static void test_watertight(void **state)
{
    tmesh m = bumpy(3);
    geom_ray_scene *s = scene_of(&m);
    size_t nr = m.nv + 3 * m.nt, i, leaks = 0, doubles = 0, eleak[2] = {0, 0};
    double *rays = malloc(nr * 6 * sizeof(double)), *te = malloc(nr * sizeof(double));
    double o[3] = {3.01, -2.02, 0.97};
    int robust;
    (void)state;
    for (i = 0; i < nr; i++) {
        double tgt[3];
        int k;
        if (i < m.nv) {
            memcpy(tgt, m.p + 3 * i, sizeof tgt);
        } else {
            size_t t = (i - m.nv) / 3, e = (i - m.nv) % 3;
            const double *a = m.p + 3 * m.t[3 * t + e], *b = m.p + 3 * m.t[3 * t + (e + 1) % 3];
            for (k = 0; k < 3; k++) tgt[k] = 0.5 * (a[k] + b[k]);
        }
        for (k = 0; k < 3; k++) {
            rays[6 * i + k] = o[k];
            rays[6 * i + 3 + k] = tgt[k] - o[k];
        }
    }
    for (i = 0; i < nr; i++) {
        geom_ray r;
        geom_ray_hit h[4];
        size_t n = 0;
        int found = 0;
        r.origin = geom_vec3_make(rays[6 * i], rays[6 * i + 1], rays[6 * i + 2]);
        r.dir = geom_vec3_make(rays[6 * i + 3], rays[6 * i + 4], rays[6 * i + 5]);
        r.tmin = 0;
        r.tmax = INFINITY;
        assert_int_equal(geom_ray_scene_all(s, &r, h, 4, &n), GEOM_OK);
        if (n == 0) leaks++;
        if (n > 1) doubles++;
        assert_int_equal(geom_ray_scene_closest(s, &r, h, &found), GEOM_OK);
        if (!found) leaks++;
    }
    for (robust = 0; robust < 2; robust++) {
        assert_int_equal(gv_embree_closest(m.p, m.nv, m.t, m.nt, robust, rays, nr, te, NULL), 0);
        for (i = 0; i < nr; i++) eleak[robust] += isnan(te[i]);
    }
    printf("watertight: %zu rays through vertices and edge midpoints: libgeom %zu leaks, %zu double hits; "
           "embree leaks: default %zu, robust %zu\n",
           nr, leaks, doubles, eleak[0], eleak[1]);
    assert_int_equal(leaks, 0);
    assert_int_equal(doubles, 0);
    geom_ray_scene_destroy(s);
    free(rays);
    free(te);
    free(m.p);
    free(m.t);
}

static void test_nonfinite(void **state)
{
    tmesh m = icosphere(2);
    geom_ray_scene *s = scene_of(&m);
    const double bad[] = {NAN, INFINITY, -INFINITY};
    int i, k;
    (void)state;
    for (i = 0; i < 3; i++)
        for (k = 0; k < 6; k++) {
            double v[6] = {0.1, 0.2, 0.3, 1, 0.5, 0.25};
            geom_ray r;
            geom_ray_hit h;
            int found = 1;
            v[k] = bad[i];
            r.origin = geom_vec3_make(v[0], v[1], v[2]);
            r.dir = geom_vec3_make(v[3], v[4], v[5]);
            r.tmin = 0;
            r.tmax = INFINITY;
            assert_int_equal(geom_ray_scene_closest(s, &r, &h, &found), GEOM_ERR_INVALID_ARG);
            assert_int_equal(found, 0);
        }
    geom_ray_scene_destroy(s);
    free(m.p);
    free(m.t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_camera_smooth),
        cmocka_unit_test(test_camera_bumpy),
        cmocka_unit_test(test_watertight),
        cmocka_unit_test(test_nonfinite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
