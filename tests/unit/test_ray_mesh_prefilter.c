/*
 * The float pre-test of a mesh's leaf triangles (ray/mesh.c: pk_filter)
 * must never drop a triangle the exact watertight test hits. Checked
 * through the public scene query in all-hits mode against brute force
 * (geom_ray_triangle, the exact test alone, on every triangle): the same
 * number of hits on every ray, and the same closest t and triangle.
 *   - an icosphere scaled by 10^e and moved to offsets where the float
 *     rounding of vertices and origin is large against the triangles
 *     (1, 1e3, 1e5 with size 1e-2, 1e7 with size 1), rays from inside aimed
 *     exactly at vertices and edge midpoints (the rays the float test is
 *     closest to getting wrong: edge functions exactly zero);
 *   - soups of slivers (one vertex within 1e-12 relative of an edge) and
 *     needles, with rays aimed at points of their edges and vertices and at
 *     random points near them;
 *   - rays nearly parallel to a triangle's plane (grazing);
 *   - the wide tree's quantized boxes: axis-parallel rays through every
 *     vertex of triangles of sizes 1e-4 to 1 (in the planes of the leaf
 *     boxes: a box rounded inward drops them) and rays aimed at vertices.
 * Zero misses and zero extra hits are required; the test also counts the
 * rays whose answer has a hit within a relative 1e-6 of an edge (where a
 * plain float test without the bound would err) and requires many.
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

static uint64_t rng = 0x2545f4914f6cdd1dull;
static double urand(void)
{
    return ray_urand(&rng);
}

/* Hits by brute force: count, and the closest (t, triangle). */
static size_t brute(const double *p, const uint32_t *t, size_t nt, const geom_ray *r, double *tc, uint32_t *ic,
                    int *near_edge)
{
    size_t i, n = 0;
    *tc = INFINITY;
    *ic = UINT32_MAX;
    for (i = 0; i < nt; i++) {
        geom_ray_hit h;
        if (!geom_ray_triangle(r, p + 3 * t[3 * i], p + 3 * t[3 * i + 1], p + 3 * t[3 * i + 2], &h)) continue;
        n++;
        if (h.t < *tc) { *tc = h.t; *ic = (uint32_t)i; }
        {
            double w = 1 - h.u - h.v;
            if (fabs(h.u) < 1e-6 || fabs(h.v) < 1e-6 || fabs(w) < 1e-6) *near_edge = 1;
        }
    }
    return n;
}

/* Every ray against scene s (the triangles p, t): same hits as brute force.
 * Returns the number of rays with a hit near an edge. */
static size_t check(geom_ray_scene *s, const double *p, const uint32_t *t, size_t nt, const geom_ray *rays,
                    size_t nr)
{
    static geom_ray_hit h[64];
    size_t i, nedge = 0;
    for (i = 0; i < nr; i++) {
        double tc;
        uint32_t ic;
        int ne = 0, found = 0;
        size_t nb = brute(p, t, nt, &rays[i], &tc, &ic, &ne), n = 0;
        geom_ray_hit hc;
        assert_int_equal(geom_ray_scene_all(s, &rays[i], h, 64, &n), GEOM_OK);
        if (n != nb)
            fail_msg("ray %zu o (%.17g %.17g %.17g) d (%.17g %.17g %.17g): %zu hits, brute force %zu", i,
                     rays[i].origin.x, rays[i].origin.y, rays[i].origin.z, rays[i].dir.x, rays[i].dir.y,
                     rays[i].dir.z, n, nb);
        assert_int_equal(geom_ray_scene_closest(s, &rays[i], &hc, &found), GEOM_OK);
        assert_int_equal(found, nb > 0);
        if (found) {
            assert_true(hc.t == tc);
            assert_int_equal(hc.prim, ic);
        }
        nedge += (size_t)ne;
    }
    return nedge;
}

static geom_ray mk(const double o[3], const double tgt[3])
{
    return mkray(o[0], o[1], o[2], tgt[0] - o[0], tgt[1] - o[1], tgt[2] - o[2]);
}

static void sphere_case(double off, double size)
{
    tmesh m = icosphere(3);
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray *rays;
    size_t i, nr = 0, nedge;
    const double o[3] = {off + 0.1 * size, off - 0.2 * size, off + 0.05 * size};
    for (i = 0; i < 3 * m.nv; i++) m.p[i] = off + size * m.p[i];
    assert_int_equal(geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    rays = malloc((m.nv + 3 * m.nt) * sizeof *rays);
    for (i = 0; i < m.nv + 3 * m.nt; i++) {
        double tgt[3];
        tmesh_target(&m, i, tgt);
        rays[nr++] = mk(o, tgt);
    }
    nedge = check(s, m.p, m.t, m.nt, rays, nr);
    print_message("sphere at %g size %g: %zu rays, %zu near an edge\n", off, size, nr, nedge);
    assert_true(nedge > nr / 2);
    free(rays);
    free(m.p);
    free(m.t);
    geom_ray_scene_destroy(s);
}

static void test_sphere_unit(void **state)
{
    (void)state;
    sphere_case(0, 1);
}

static void test_sphere_offsets(void **state)
{
    (void)state;
    sphere_case(1e3, 1);
    sphere_case(1e5, 1e-2);
    sphere_case(1e7, 1);
    sphere_case(-3.3e4, 7e-3);
}

/* Slivers and needles in a box of size 1 around c, rays aimed at their
 * edges, vertices and nearby points from random origins, and grazing rays
 * in their planes. */
static void test_slivers(void **state)
{
    const size_t nt = 400, nr = 20000;
    double *p = malloc(9 * nt * sizeof(double));
    uint32_t *t = malloc(3 * nt * sizeof(uint32_t));
    geom_ray *rays = malloc(nr * sizeof *rays);
    const double cs[2] = {0.25, 4096.5};
    int ci;
    (void)state;
    for (ci = 0; ci < 2; ci++) {
        const double c = cs[ci];
        geom_ray_scene *s = geom_ray_scene_create(NULL);
        size_t i, nedge;
        for (i = 0; i < nt; i++) {
            double *a = p + 9 * i, *b = a + 3, *q = a + 6, f;
            int k;
            for (k = 0; k < 3; k++) {
                a[k] = c + urand();
                b[k] = c + urand();
            }
            f = urand();
            for (k = 0; k < 3; k++) {
                /* a point of segment ab moved off it by 1e-12 (a sliver) or
                 * by 1e-3 (a needle-ish triangle) */
                double dev = (i % 2 ? 1e-12 : 1e-3) * (urand() - 0.5);
                q[k] = a[k] + f * (b[k] - a[k]) + dev;
            }
            t[3 * i] = (uint32_t)(3 * i);
            t[3 * i + 1] = (uint32_t)(3 * i + 1);
            t[3 * i + 2] = (uint32_t)(3 * i + 2);
        }
        assert_int_equal(geom_ray_scene_add_triangles(s, p, 3 * nt, t, nt, NULL, NULL), GEOM_OK);
        assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
        for (i = 0; i < nr; i++) {
            const double *v = p + 9 * (size_t)(urand() * (double)nt);
            double o[3], tgt[3], f = urand();
            int k, kind = (int)(i % 4), e = (int)(urand() * 3);
            for (k = 0; k < 3; k++) o[k] = c + 0.5 + 3 * (urand() - 0.5);
            for (k = 0; k < 3; k++) {
                const double *a = v + 3 * e, *b = v + 3 * ((e + 1) % 3);
                if (kind == 0) tgt[k] = a[k];                         /* a vertex */
                else if (kind == 1) tgt[k] = a[k] + f * (b[k] - a[k]); /* a point of an edge */
                else tgt[k] = a[k] + f * (b[k] - a[k]) + 1e-9 * (urand() - 0.5); /* near it */
            }
            if (kind == 3) { /* grazing: origin nearly in the triangle's plane */
                for (k = 0; k < 3; k++) o[k] = v[k] + 2 * (v[3 + k] - v[k]) - 1.5 * (v[6 + k] - v[k]) + 1e-10 * urand();
            }
            rays[i] = mk(o, tgt);
        }
        nedge = check(s, p, t, nt, rays, nr);
        print_message("slivers at %g: %zu rays, %zu near an edge\n", c, nr, nedge);
        assert_true(nedge > nr / 10);
        geom_ray_scene_destroy(s);
    }
    free(p);
    free(t);
    free(rays);
}

/* The wide tree's quantized boxes (8-bit planes relative to the parent)
 * must contain every triangle: rays parallel to an axis through each vertex
 * lie exactly in the planes of the leaf boxes the vertex bounds, so a box
 * rounded inward anywhere drops them (the tree would then miss hits brute
 * force finds), and rays from random directions aimed at the vertices.
 * Triangles of sizes 1e-4 to 1 in a unit box, so that a node's children
 * differ in size by orders of magnitude (coarse 8-bit steps next to small
 * boxes), at offsets where the float rounding is coarse too. */
static void test_quantized_boxes(void **state)
{
    const size_t nt = 1500;
    double *p = malloc(9 * nt * sizeof(double));
    uint32_t *t = malloc(3 * nt * sizeof(uint32_t));
    geom_ray *rays = malloc(3 * nt * 8 * sizeof *rays);
    const double cs[3] = {0, 1000.3, -33333.7};
    int ci;
    (void)state;
    for (ci = 0; ci < 3; ci++) {
        const double c = cs[ci];
        geom_ray_scene *s = geom_ray_scene_create(NULL);
        size_t i, nr = 0;
        for (i = 0; i < nt; i++) {
            double sz = pow(10, -4 * urand()), b[3];
            int k, v;
            for (k = 0; k < 3; k++) b[k] = c + urand();
            for (v = 0; v < 3; v++)
                for (k = 0; k < 3; k++) p[9 * i + 3 * v + k] = b[k] + sz * (urand() - 0.5);
            t[3 * i] = (uint32_t)(3 * i);
            t[3 * i + 1] = (uint32_t)(3 * i + 1);
            t[3 * i + 2] = (uint32_t)(3 * i + 2);
        }
        assert_int_equal(geom_ray_scene_add_triangles(s, p, 3 * nt, t, nt, NULL, NULL), GEOM_OK);
        assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
        for (i = 0; i < 3 * nt; i++) {
            const double *v = p + 3 * i;
            int a;
            for (a = 0; a < 6; a++) {
                double o[3] = {v[0], v[1], v[2]}, d[3] = {0, 0, 0};
                d[a / 2] = a % 2 ? -1 : 1;
                o[a / 2] -= 3 * d[a / 2];
                rays[nr++] = mkray(o[0], o[1], o[2], d[0], d[1], d[2]);
            }
            for (a = 0; a < 2; a++) {
                double o[3];
                int k;
                for (k = 0; k < 3; k++) o[k] = c + 0.5 + 3 * (urand() - 0.5);
                rays[nr++] = mk(o, v);
            }
        }
        check(s, p, t, nt, rays, nr);
        geom_ray_scene_destroy(s);
    }
    free(p);
    free(t);
    free(rays);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_unit),
        cmocka_unit_test(test_sphere_offsets),
        cmocka_unit_test(test_slivers),
        cmocka_unit_test(test_quantized_boxes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
