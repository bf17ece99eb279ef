/*
 * geom_ray_scene_closest_many (the interleaved traversal of eight rays at a
 * time, ray/mesh.c) must answer every ray bit for bit as
 * geom_ray_scene_closest does one at a time, on both vector paths (SSE2 and
 * AVX2, forced with the internal switch geom__ray_scene_simd), and the
 * closest t must be brute force's (geom_ray_triangle on every triangle):
 *   - an icosphere from inside (rays aimed exactly at vertices and edge
 *     midpoints: edge functions zero) and from outside (random), at unit
 *     scale and at 1e3; at 1e20 (no wide tree: one ray at a time);
 *   - rays with +-0 direction components (the decoding node test), limited
 *     [tmin, tmax] (pruned early, empty when tmin > tmax), origins beyond
 *     2^60 (the double node test, traced alone inside the batch), invalid
 *     rays (NaN, Inf, zero direction: found = 0, GEOM_ERR_INVALID_ARG, the
 *     other rays still answered), mixed in every eighth position so that
 *     the eight slots refill at every offset;
 *   - batch sizes 0, 1, 7, 9 and thousands; a scene of two objects (not a
 *     single mesh: one ray at a time); NULL arguments and an unbuilt scene.
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
#include "unit/ray_testutil.h"

/* Internal (ray/ray_internal.h): force every mesh of s onto one path. */
int geom__ray_scene_simd(geom_ray_scene *s, int isa);

static uint64_t rng = 0x51ab2c3d4e5f6071ull;
static double urand(void)
{
    return ray_urand(&rng);
}

/* The closest t by brute force (INFINITY: none) over [tmin, tmax]. */
static double brute(const tmesh *m, const geom_ray *r)
{
    size_t i;
    double tc = INFINITY;
    for (i = 0; i < m->nt; i++) {
        geom_ray_hit h;
        if (geom_ray_triangle(r, m->p + 3 * m->t[3 * i], m->p + 3 * m->t[3 * i + 1], m->p + 3 * m->t[3 * i + 2],
                              &h) &&
            h.t < tc)
            tc = h.t;
    }
    return tc;
}

/* The batch against one-at-a-time on both paths; m (may be NULL) for brute
 * force. Returns the number of rays with a hit. */
static size_t check_batch(geom_ray_scene *s, const tmesh *m, const geom_ray *rays, size_t n, int expect_invalid)
{
    geom_ray_hit *hb = malloc((n ? n : 1) * sizeof *hb), h1;
    int *fb = malloc((n ? n : 1) * sizeof *fb);
    size_t i, nhit = 0;
    int path;
    for (path = 0; path < 2; path++) {
        geom_status st;
        geom__ray_scene_simd(s, path);
        memset(fb, 0x55, (n ? n : 1) * sizeof *fb);
        st = geom_ray_scene_closest_many(s, rays, n, hb, fb);
        assert_int_equal(st, expect_invalid ? GEOM_ERR_INVALID_ARG : GEOM_OK);
        nhit = 0;
        for (i = 0; i < n; i++) {
            int f1 = 0;
            geom_status s1 = geom_ray_scene_closest(s, &rays[i], &h1, &f1);
            assert_true(s1 == GEOM_OK || s1 == GEOM_ERR_INVALID_ARG);
            if (fb[i] != f1)
                fail_msg("path %d ray %zu o (%.17g %.17g %.17g) d (%.17g %.17g %.17g): batch found %d, single %d",
                         path, i, rays[i].origin.x, rays[i].origin.y, rays[i].origin.z, rays[i].dir.x,
                         rays[i].dir.y, rays[i].dir.z, fb[i], f1);
            if (f1) {
                assert_true(ray_same_hit(&hb[i], &h1));
                nhit++;
            }
            if (m && s1 == GEOM_OK) {
                double tc = brute(m, &rays[i]);
                assert_int_equal(f1, tc < INFINITY);
                if (f1) assert_true(h1.t == tc);
            }
        }
    }
    free(hb);
    free(fb);
    return nhit;
}

/* Rays at the sphere (centre off, radius size): aimed at its vertices and
 * edge midpoints from inside, random from outside, and every eighth a
 * special ray (zero components, limited or empty range, far origin, and,
 * with invalid, NaN / Inf / zero direction). */
static size_t make_rays(const tmesh *m, double off, double size, int invalid, geom_ray *rays)
{
    size_t i, nr = 0, nin = m->nv + 3 * m->nt;
    const double o[3] = {off + 0.1 * size, off - 0.2 * size, off + 0.05 * size};
    for (i = 0; i < nin + 3000; i++) {
        geom_ray r;
        if (i < nin) {
            double tgt[3];
            tmesh_target(m, i, tgt);
            r = mkray(o[0], o[1], o[2], tgt[0] - o[0], tgt[1] - o[1], tgt[2] - o[2]);
        } else {
            double a[3], b[3];
            int k;
            for (k = 0; k < 3; k++) {
                a[k] = off + size * 4 * (urand() - 0.5);
                b[k] = off + size * 1.2 * (urand() - 0.5);
            }
            r = mkray(a[0], a[1], a[2], b[0] - a[0], b[1] - a[1], b[2] - a[2]);
        }
        if (i % 8 == (i / 8) % 8) {
            switch ((i / 64) % 8) {
            case 0: r.dir.x = 0.0; break;
            case 1: r.dir.y = -0.0; r.dir.z = 0.0; break;
            case 2: r.tmax = 0.5; r.tmin = 0.25; break;
            case 3: r.tmin = 2; r.tmax = 1; break; /* empty */
            case 4: /* an origin beyond 2^60 aimed back at the sphere */
                r.origin.x = off + 3e18;
                r.dir.x = off - r.origin.x;
                break;
            case 5: if (invalid) r.origin.y = NAN; break;
            case 6: if (invalid) r.dir.x = r.dir.y = r.dir.z = 0; break;
            default: if (invalid) r.dir.z = INFINITY; break;
            }
        }
        rays[nr++] = r;
    }
    return nr;
}

static void sphere_case(double off, double size, int invalid)
{
    tmesh m = icosphere(3);
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray *rays = malloc((m.nv + 3 * m.nt + 3000) * sizeof *rays);
    size_t i, nr, nhit;
    for (i = 0; i < 3 * m.nv; i++) m.p[i] = off + size * m.p[i];
    assert_int_equal(geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    nr = make_rays(&m, off, size, invalid, rays);
    nhit = check_batch(s, &m, rays, nr, invalid);
    print_message("sphere at %g size %g: %zu rays, %zu with a hit\n", off, size, nr, nhit);
    assert_true(nhit > nr / 2);
    /* small batches at every offset */
    check_batch(s, &m, rays + 5, 0, 0);
    check_batch(s, &m, rays + 3, 1, 0);
    check_batch(s, &m, rays + 11, 7, 0);
    check_batch(s, &m, rays + 17, 9, 0);
    free(rays);
    free(m.p);
    free(m.t);
    geom_ray_scene_destroy(s);
}

static void test_sphere(void **state)
{
    (void)state;
    sphere_case(0, 1, 0);
    sphere_case(0, 1, 1);
    sphere_case(1e3, 1, 1);
    sphere_case(1e20, 1e8, 1); /* no wide tree */
}

static void test_two_objects_and_args(void **state)
{
    tmesh m = icosphere(2);
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    const double c[3] = {0.5, 0, 0};
    geom_ray *rays = malloc((m.nv + 3 * m.nt + 3000) * sizeof *rays);
    geom_ray_hit h;
    int f = 7;
    size_t nr;
    (void)state;
    assert_int_equal(geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, NULL, NULL), GEOM_OK);
    /* unbuilt: every found 0 */
    nr = make_rays(&m, 0, 1, 0, rays);
    assert_int_equal(geom_ray_scene_closest_many(s, rays, 1, &h, &f), GEOM_ERR_INVALID_ARG);
    assert_int_equal(f, 0);
    assert_int_equal(geom_ray_scene_add_sphere(s, c, 0.3, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    check_batch(s, NULL, rays, nr, 0);
    assert_int_equal(geom_ray_scene_closest_many(NULL, rays, 1, &h, &f), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_closest_many(s, NULL, 1, &h, &f), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_closest_many(s, rays, 1, NULL, &f), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_closest_many(s, rays, 1, &h, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_closest_many(s, NULL, 0, NULL, NULL), GEOM_OK);
    free(rays);
    free(m.p);
    free(m.t);
    geom_ray_scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_two_objects_and_args),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
