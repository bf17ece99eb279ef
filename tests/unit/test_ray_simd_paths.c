/*
 * The mesh traversal's two vector paths (ray/mesh.c: SSE2, and AVX2 + FMA
 * chosen at build when the CPU has them) must give the same hits, bit for
 * bit, and the same hits as brute force (geom_ray_triangle, the exact test
 * alone, on every triangle). Each scene is built once, and every ray goes
 * through both paths (forced with the internal switch geom__ray_scene_simd)
 * in closest, any and all modes:
 *   - an icosphere at unit scale and at offsets 1e3, 1e5 (size 1e-2) and
 *     1e7, rays from inside aimed exactly at its vertices and edge
 *     midpoints (edge functions exactly zero, the rays the float pre-tests
 *     are closest to getting wrong) and random rays from outside;
 *   - a soup of slivers and random triangles with rays aimed at their
 *     vertices and edges, axis-parallel rays through vertices (in the
 *     planes of the quantized leaf boxes), rays with +-0 direction
 *     components, and grazing rays;
 *   - the icosphere at 1e20, size 1e8 (boxes beyond the float test's range: both
 *     paths take the double test, still the same answers).
 * On a CPU without AVX2 both runs take the SSE2 path (printed).
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

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double urand(void)
{
    return ray_urand(&rng);
}

/* Number of triangles the exact test hits. */
static size_t brute(const double *p, const uint32_t *t, size_t nt, const geom_ray *r)
{
    size_t i, n = 0;
    for (i = 0; i < nt; i++) {
        geom_ray_hit h;
        n += (size_t)geom_ray_triangle(r, p + 3 * t[3 * i], p + 3 * t[3 * i + 1], p + 3 * t[3 * i + 2], &h);
    }
    return n;
}

#define MAXH 64

static int last_avx; /* both_paths's last scene ran the AVX2 path */

/* Every ray through both paths: the same answers bit for bit, and the
 * brute-force number of hits. Returns the number of rays with a hit. */
static size_t both_paths(geom_ray_scene *s, const double *p, const uint32_t *t, size_t nt, const geom_ray *rays,
                         size_t nr)
{
    static geom_ray_hit ha[2][MAXH];
    size_t i, nhit = 0;
    int avx;
    geom__ray_scene_simd(s, 1);
    avx = geom__ray_scene_simd(s, 1) == 1; /* the previous value: 1 when the switch took */
    if (!avx) print_message("no wide tree (far from the origin for its size) or no AVX2: SSE2 or double only\n");
    last_avx = avx;
    for (i = 0; i < nr; i++) {
        geom_ray_hit hc[2];
        int fc[2] = {0, 0}, fa[2] = {0, 0}, path;
        size_t na[2] = {0, 0}, nb = brute(p, t, nt, &rays[i]), j;
        for (path = 0; path < 2; path++) {
            geom__ray_scene_simd(s, path);
            assert_int_equal(geom_ray_scene_closest(s, &rays[i], &hc[path], &fc[path]), GEOM_OK);
            assert_int_equal(geom_ray_scene_any(s, &rays[i], &fa[path]), GEOM_OK);
            assert_int_equal(geom_ray_scene_all(s, &rays[i], ha[path], MAXH, &na[path]), GEOM_OK);
        }
        if (na[0] != nb || na[1] != nb)
            fail_msg("ray %zu o (%.17g %.17g %.17g) d (%.17g %.17g %.17g): %zu (SSE2) and %zu (AVX2) hits, "
                     "brute force %zu",
                     i, rays[i].origin.x, rays[i].origin.y, rays[i].origin.z, rays[i].dir.x, rays[i].dir.y,
                     rays[i].dir.z, na[0], na[1], nb);
        assert_int_equal(fc[0], nb > 0);
        assert_int_equal(fc[1], nb > 0);
        assert_int_equal(fa[0], nb > 0);
        assert_int_equal(fa[1], nb > 0);
        if (fc[0]) assert_true(ray_same_hit(&hc[0], &hc[1]));
        for (j = 0; j < na[0] && j < MAXH; j++) assert_true(ray_same_hit(&ha[0][j], &ha[1][j]));
        nhit += nb > 0;
    }
    return nhit;
}

static void sphere_case(double off, double size)
{
    tmesh m = icosphere(3);
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    size_t i, nr = 0, nin = m.nv + 3 * m.nt, nhit;
    geom_ray *rays = malloc((nin + 2000) * sizeof *rays);
    const double o[3] = {off + 0.1 * size, off - 0.2 * size, off + 0.05 * size};
    for (i = 0; i < 3 * m.nv; i++) m.p[i] = off + size * m.p[i];
    assert_int_equal(geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    for (i = 0; i < nin; i++) {
        double tgt[3];
        tmesh_target(&m, i, tgt);
        rays[nr++] = mkray(o[0], o[1], o[2], tgt[0] - o[0], tgt[1] - o[1], tgt[2] - o[2]);
    }
    for (i = 0; i < 2000; i++) { /* from outside, toward a random point near the sphere */
        double a[3], b[3];
        int k;
        for (k = 0; k < 3; k++) {
            a[k] = off + size * 4 * (urand() - 0.5);
            b[k] = off + size * 1.2 * (urand() - 0.5);
        }
        rays[nr++] = mkray(a[0], a[1], a[2], b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    }
    nhit = both_paths(s, m.p, m.t, m.nt, rays, nr);
    print_message("sphere at %g size %g: %zu rays, %zu with a hit\n", off, size, nr, nhit);
    assert_true(nhit >= nin);
    free(rays);
    free(m.p);
    free(m.t);
    geom_ray_scene_destroy(s);
}

static void test_sphere_unit(void **state)
{
    (void)state;
    sphere_case(0, 1);
    assert_int_equal(last_avx, ray_cpu_avx2());
}

static void test_sphere_offsets(void **state)
{
    (void)state;
    sphere_case(1e3, 1);
    sphere_case(1e5, 1e-2);
    sphere_case(1e7, 1);
    sphere_case(1e20, 1e8); /* the double slab test on both paths */
}

static void test_soup(void **state)
{
    const size_t nt = 600, nr = 12000;
    double *p = malloc(9 * nt * sizeof(double));
    uint32_t *t = malloc(3 * nt * sizeof(uint32_t));
    geom_ray *rays = malloc(nr * sizeof *rays);
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    size_t i, nhit;
    (void)state;
    for (i = 0; i < nt; i++) {
        double *a = p + 9 * i, *b = a + 3, *q = a + 6, f = urand();
        int k;
        for (k = 0; k < 3; k++) {
            a[k] = 0.3 + urand();
            b[k] = a[k] + 0.2 * (urand() - 0.5);
        }
        for (k = 0; k < 3; k++) /* every third a sliver */
            q[k] = a[k] + f * (b[k] - a[k]) + (i % 3 ? 0.1 : 1e-12) * (urand() - 0.5);
        t[3 * i] = (uint32_t)(3 * i);
        t[3 * i + 1] = (uint32_t)(3 * i + 1);
        t[3 * i + 2] = (uint32_t)(3 * i + 2);
    }
    assert_int_equal(geom_ray_scene_add_triangles(s, p, 3 * nt, t, nt, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    for (i = 0; i < nr; i++) {
        const double *v = p + 9 * (size_t)(urand() * (double)nt);
        double o[3], d[3], f = urand();
        int k, kind = (int)(i % 5), e = (int)(urand() * 3), ax = (int)(urand() * 3);
        const double *a = v + 3 * e, *b = v + 3 * ((e + 1) % 3);
        for (k = 0; k < 3; k++) o[k] = 0.8 + 3 * (urand() - 0.5);
        for (k = 0; k < 3; k++) {
            double tgt = kind == 0 ? a[k] : a[k] + f * (b[k] - a[k]); /* a vertex, a point of an edge */
            d[k] = tgt - o[k];
        }
        if (kind == 2) { /* parallel to an axis through a vertex: in leaf box planes */
            for (k = 0; k < 3; k++) o[k] = a[k];
            o[ax] = -1;
            d[0] = d[1] = d[2] = (i / 5) % 2 ? -0.0 : 0.0;
            d[ax] = 1;
        } else if (kind == 3) { /* one zero (+0 or -0) direction component */
            d[ax] = (i / 5) % 2 ? -0.0 : 0.0;
            o[ax] = a[ax];
        } else if (kind == 4) { /* grazing: origin nearly in the triangle's plane */
            for (k = 0; k < 3; k++) {
                o[k] = v[k] + 2 * (v[3 + k] - v[k]) - 1.5 * (v[6 + k] - v[k]) + 1e-10 * urand();
                d[k] = a[k] + f * (b[k] - a[k]) - o[k];
            }
        }
        rays[i] = mkray(o[0], o[1], o[2], d[0], d[1], d[2]);
    }
    nhit = both_paths(s, p, t, nt, rays, nr);
    print_message("soup: %zu rays, %zu with a hit\n", nr, nhit);
    assert_int_equal(last_avx, ray_cpu_avx2());
    assert_true(nhit > nr / 3);
    geom_ray_scene_destroy(s);
    free(p);
    free(t);
    free(rays);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_unit),
        cmocka_unit_test(test_sphere_offsets),
        cmocka_unit_test(test_soup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
