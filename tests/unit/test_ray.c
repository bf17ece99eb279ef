/*
 * ray: every representation against closed forms or brute force: spheres
 * (including a small sphere far from the origin), planes, disks, boxes,
 * quadrics (capped cylinder), tori (grazing rays against the exact tangent
 * configuration), watertight meshes (rays from inside a closed icosphere
 * exactly through its vertices and edge midpoints: no leak, no double hit),
 * CSG, instances, NURBS (the exact rational sphere), implicit expressions
 * and sampled volumes; NaN/Inf rays; the offset helper at scales 1e-4..1e7.
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

static geom_ray_scene *built(geom_ray_scene *s)
{
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    return s;
}

static int closest(const geom_ray_scene *s, geom_ray r, geom_ray_hit *h)
{
    int found = 0;
    assert_int_equal(geom_ray_scene_closest(s, &r, h, &found), GEOM_OK);
    return found;
}

static size_t all(const geom_ray_scene *s, geom_ray r, geom_ray_hit *h, size_t cap)
{
    size_t n = 0;
    geom_status st = geom_ray_scene_all(s, &r, h, cap, &n);
    assert_true(st == GEOM_OK || st == GEOM_ERR_LIMIT);
    return n;
}

/* ------------------------------------------------------------- analytic */

static void test_sphere(void **state)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double c[3] = {1, 2, 3};
    geom_ray_hit h[4];
    int i;
    (void)state;
    assert_int_equal(geom_ray_scene_add_sphere(s, c, 2, NULL), GEOM_OK);
    built(s);
    assert_true(closest(s, mkray(1, 2, -10, 0, 0, 2), h));
    assert_true(fabs(h[0].t - 5.5) < 1e-14);
    assert_true(fabs(h[0].ng.z + 1) < 1e-15);
    assert_true(h[0].enter);
    assert_int_equal(all(s, mkray(1, 2, -10, 0, 0, 2), h, 4), 2);
    assert_true(fabs(h[1].t - 7.5) < 1e-14 && !h[1].enter);
    /* from inside: only the exit */
    assert_int_equal(all(s, mkray(1, 2, 3, 1, 0, 0), h, 4), 1);
    assert_true(fabs(h[0].t - 2) < 1e-15);
    /* random rays against the closed form (line distance) */
    for (i = 0; i < 1000; i++) {
        geom_ray r = mkray(urand() * 20 - 10, urand() * 20 - 10, urand() * 20 - 10, urand() - 0.5,
                           urand() - 0.5, urand() - 0.5);
        geom_vec3 f = geom_vec3_sub(r.origin, geom_vec3_make(1, 2, 3));
        double a = geom_vec3_dot(r.dir, r.dir), b = geom_vec3_dot(f, r.dir), cc = geom_vec3_dot(f, f) - 4;
        double disc = b * b - a * cc;
        size_t n = all(s, r, h, 4);
        if (disc > 1e-9 * a) {
            double t0 = (-b - sqrt(disc)) / a, t1 = (-b + sqrt(disc)) / a;
            size_t expect = (t0 >= 0) + (t1 >= 0);
            assert_int_equal(n, expect);
            if (n == 2) assert_true(fabs(h[0].t - t0) <= 1e-9 * (1 + fabs(t0)));
            if (n >= 1) assert_true(fabs(h[n - 1].t - t1) <= 1e-9 * (1 + fabs(t1)));
        } else if (disc < -1e-9 * a) {
            assert_int_equal(n, 0);
        }
    }
    geom_ray_scene_destroy(s);
}

/* A sphere of radius 1e-3 at 1e7: RTG ch. 7's formulation keeps the hit on the
 * surface; the naive b^2 - 4ac loses everything. */
static void test_sphere_far(void **state)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double c[3] = {1e7, -1e7, 1e7};
    geom_ray_hit h;
    int i, hits = 0;
    (void)state;
    assert_int_equal(geom_ray_scene_add_sphere(s, c, 1e-3, NULL), GEOM_OK);
    built(s);
    for (i = 0; i < 200; i++) {
        double ox = 1e7 + (urand() - 0.5) * 1.6e-3, oy = -1e7 + (urand() - 0.5) * 1.6e-3;
        geom_ray r = mkray(ox, oy, 0, 0, 0, 1);
        double rho = hypot(ox - 1e7, oy + 1e7);
        if (closest(s, r, &h)) {
            double dz = h.t - 1e7;
            hits++;
            assert_true(rho <= 1e-3 * (1 + 1e-9));
            /* the exact first hit: z = 1e7 - sqrt(r^2 - rho^2) */
            assert_true(fabs(dz + sqrt(1e-6 - rho * rho)) <= 1e-8 + h.t_error);
            assert_true(fabs(geom_vec3_length(geom_vec3_sub(h.point, geom_vec3_make(c[0], c[1], c[2]))) - 1e-3) <
                        1e-8);
        } else {
            assert_true(rho >= 1e-3 * (1 - 1e-6));
        }
    }
    assert_true(hits > 100);
    geom_ray_scene_destroy(s);
}

static void test_plane_disk_box(void **state)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double p[3] = {0, 0, 1}, n[3] = {0, 0, 2}, c[3] = {0, 0, 2}, mn[3] = {-1, -1, 3}, mx[3] = {1, 1, 4};
    geom_ray_hit h[8];
    size_t k;
    (void)state;
    assert_int_equal(geom_ray_scene_add_plane(s, p, n, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_disk(s, c, n, 0.5, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_box(s, mn, mx, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_box(s, mn, mn, NULL), GEOM_OK); /* a point box */
    built(s);
    k = all(s, mkray(0.25, 0, 0, 0, 0, 1), h, 8);
    assert_int_equal(k, 4);
    assert_true(h[0].t == 1 && h[0].object == 0 && !h[0].enter);
    assert_true(h[1].t == 2 && h[1].object == 1);
    assert_true(h[2].t == 3 && h[2].object == 2 && h[2].enter && h[2].prim == 4);
    assert_true(h[3].t == 4 && !h[3].enter && h[3].prim == 5);
    /* outside the disk, through the box edge x = 1 exactly */
    k = all(s, mkray(1, 0, 0, 0, 0, 1), h, 8);
    assert_int_equal(k, 3);
    /* a ray parallel to the box faces, inside the slab */
    k = all(s, mkray(-5, 0, 3.5, 1, 0, 0), h, 8);
    assert_int_equal(k, 2);
    assert_true(h[0].t == 4 && h[1].t == 6);
    /* the point box is hit by a ray through it */
    k = all(s, mkray(-1, -1, 10, 0, 0, -1), h, 8);
    assert_true(k >= 3);
    geom_ray_scene_destroy(s);
}

static void test_quadric(void **state)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double q[10], prm[1] = {1}, clip[6] = {-2, -2, -1, 2, 2, 1};
    geom_ray_hit h[8];
    size_t k;
    (void)state;
    assert_int_equal(geom_ray_quadric_make(GEOM_RAY_QUADRIC_CYLINDER, prm, q), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_quadric(s, q, clip, 1, NULL), GEOM_OK);
    built(s);
    /* along the axis: the two caps */
    k = all(s, mkray(0.5, 0, -5, 0, 0, 1), h, 8);
    assert_int_equal(k, 2);
    assert_true(h[0].t == 4 && h[0].ng.z == -1 && h[0].enter);
    assert_true(h[1].t == 6 && h[1].ng.z == 1);
    /* across: the side at x = -sqrt(1 - 0.36), + */
    k = all(s, mkray(-5, 0.6, 0, 1, 0, 0), h, 8);
    assert_int_equal(k, 2);
    assert_true(fabs(h[0].t - (5 - 0.8)) < 1e-14 && fabs(h[1].t - 5.8) < 1e-14);
    assert_true(fabs(h[0].ng.x + 0.8) < 1e-14);
    /* above the caps: miss */
    assert_int_equal(all(s, mkray(-5, 0, 1.5, 1, 0, 0), h, 8), 0);
    /* two-sheet hyperboloid, uncapped, unbounded */
    {
        geom_ray_scene *s2 = geom_ray_scene_create(NULL);
        double p2[2] = {1, 1};
        assert_int_equal(geom_ray_quadric_make(GEOM_RAY_QUADRIC_HYPERBOLOID2, p2, q), GEOM_OK);
        assert_int_equal(geom_ray_scene_add_quadric(s2, q, NULL, 0, NULL), GEOM_OK);
        built(s2);
        k = all(s2, mkray(0, 0, -5, 0, 0, 1), h, 8);
        assert_int_equal(k, 2);
        assert_true(fabs(h[0].t - 4) < 1e-14 && !h[0].enter); /* leaves the lower sheet's inside */
        assert_true(fabs(h[1].t - 6) < 1e-14 && h[1].enter);
        geom_ray_scene_destroy(s2);
    }
    geom_ray_scene_destroy(s);
}

/* Torus R = 2, r = 1. The ray z = 1 (tangent plane of the top circle) along
 * x touches the torus along the top circle: tangent at x = +-2; z slightly
 * below must give 4 roots, slightly above none (no phantom roots). */
static void test_torus(void **state)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray_hit h[8];
    size_t k;
    int i;
    (void)state;
    assert_int_equal(geom_ray_scene_add_torus(s, 2, 1, NULL), GEOM_OK);
    built(s);
    k = all(s, mkray(-5, 0, 0, 1, 0, 0), h, 8);
    assert_int_equal(k, 4);
    assert_true(fabs(h[0].t - 2) < 1e-13 && fabs(h[1].t - 4) < 1e-13 && fabs(h[2].t - 6) < 1e-13 &&
                fabs(h[3].t - 8) < 1e-13);
    assert_true(h[0].enter && !h[1].enter && h[2].enter && !h[3].enter);
    for (i = 1; i <= 8; i++) {
        double e = pow(10.0, -i);
        /* z = 1 - e: chord half-length sqrt(1 - (1-e)^2) ~ sqrt(2e) about x = +-2 */
        k = all(s, mkray(-5, 0, 1 - e, 1, 0, 0), h, 8);
        assert_int_equal(k, 4);
        {
            double w = sqrt(1 - (1 - e) * (1 - e));
            assert_true(fabs(h[0].t - (3 - w)) < 1e-6 * w + 1e-12);
            assert_true(fabs(h[3].t - (7 + w)) < 1e-6 * w + 1e-12);
        }
        k = all(s, mkray(-5, 0, 1 + e, 1, 0, 0), h, 8);
        assert_int_equal(k, 0);
    }
    /* exactly tangent: the touching points count (double roots) */
    k = all(s, mkray(-5, 0, 1, 1, 0, 0), h, 8);
    assert_true(k == 4 || k == 0);
    /* the inner equator, grazing x = +-1 in the plane z = 0 along y */
    k = all(s, mkray(1, -5, 0, 0, 1, 0), h, 8);
    assert_true(k >= 2);
    for (i = 0; i < 2000; i++) {
        geom_ray r = mkray(urand() * 8 - 4, urand() * 8 - 4, urand() * 4 - 2, urand() - 0.5, urand() - 0.5,
                           urand() - 0.5);
        size_t j;
        k = all(s, r, h, 8);
        assert_true(k <= 4);
        for (j = 0; j < k; j++) {
            geom_vec3 p = h[j].point;
            double rho = hypot(p.x, p.y), f = (rho - 2) * (rho - 2) + p.z * p.z - 1;
            assert_true(fabs(f) < 1e-9);
        }
    }
    geom_ray_scene_destroy(s);
}

/* ------------------------------------------------------------ triangles */

/* Rays from inside a closed mesh exactly through every vertex and every edge
 * midpoint: exactly one hit each (no leak, no double hit), in closest and in
 * all-hits mode, from the centre and from off-centre origins. */
static void test_watertight(void **state)
{
    tmesh m = icosphere(3);
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray_hit h[8];
    size_t i, leaks = 0, doubles = 0, rays = 0;
    int oi;
    double origins[4][3] = {{0, 0, 0}, {0.1, -0.2, 0.05}, {-0.3, 0.3, 0.3}, {1e-9, 0, 0}};
    (void)state;
    assert_int_equal(geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, NULL, NULL), GEOM_OK);
    built(s);
    for (oi = 0; oi < 4; oi++) {
        const double *o = origins[oi];
        for (i = 0; i < m.nv + m.nt * 3; i++) {
            double tgt[3];
            size_t n;
            geom_ray_hit hc;
            tmesh_target(&m, i, tgt);
            {
                geom_ray r = mkray(o[0], o[1], o[2], tgt[0] - o[0], tgt[1] - o[1], tgt[2] - o[2]);
                n = all(s, r, h, 8);
                rays++;
                if (n == 0) leaks++;
                if (n > 1) doubles++;
                if (!closest(s, r, &hc)) leaks++;
                else assert_true(!hc.enter);
            }
        }
    }
    assert_int_equal(leaks, 0);
    assert_int_equal(doubles, 0);
    assert_true(rays > 10000);
    /* a ray from outside through a vertex: enter once and leave once */
    {
        geom_ray r = mkray(2 * m.p[0], 2 * m.p[1], 2 * m.p[2], -m.p[0], -m.p[1], -m.p[2]);
        size_t n = all(s, r, h, 8);
        assert_int_equal(n, 2);
        assert_true(h[0].enter && !h[1].enter);
    }
    geom_ray_scene_destroy(s);
    free(m.p);
    free(m.t);
}

static void test_triangle_single(void **state)
{
    double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    geom_ray r = mkray(0.25, 0.25, 1, 0, 0, -1);
    geom_ray_hit h;
    (void)state;
    assert_int_equal(geom_ray_triangle(&r, a, b, c, &h), 1);
    assert_true(h.t == 1 && h.u == 0.25 && h.v == 0.25 && h.ng.z == 1 && h.enter);
    r = mkray(0.25, 0.25, 1, 0, 0, 0);
    assert_int_equal(geom_ray_triangle(&r, a, b, c, &h), 0);
    r = mkray(NAN, 0.25, 1, 0, 0, -1);
    assert_int_equal(geom_ray_triangle(&r, a, b, c, &h), 0);
    r = mkray(0.25, 0.25, 1, 0, 0, -INFINITY);
    assert_int_equal(geom_ray_triangle(&r, a, b, c, &h), 0);
    /* degenerate triangle */
    r = mkray(0, 0, 1, 0, 0, -1);
    assert_int_equal(geom_ray_triangle(&r, a, a, c, &h), 0);
}

static void test_invalid_rays(void **state)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double c[3] = {0, 0, 0};
    geom_ray_hit h[2];
    int found = 1;
    size_t n = 5;
    geom_ray bad[5];
    int i;
    (void)state;
    geom_ray_scene_add_sphere(s, c, 1, NULL);
    built(s);
    bad[0] = mkray(NAN, 0, 0, 1, 0, 0);
    bad[1] = mkray(0, 0, 0, INFINITY, 0, 0);
    bad[2] = mkray(0, 0, 0, 0, 0, 0);
    bad[3] = mkray(0, -INFINITY, 0, 1, 0, 0);
    bad[4] = mkray(0, 0, 0, 1, 0, 0);
    bad[4].tmin = NAN;
    for (i = 0; i < 5; i++) {
        assert_int_equal(geom_ray_scene_closest(s, &bad[i], h, &found), GEOM_ERR_INVALID_ARG);
        assert_int_equal(found, 0);
        assert_int_equal(geom_ray_scene_any(s, &bad[i], &found), GEOM_ERR_INVALID_ARG);
        assert_int_equal(found, 0);
        assert_int_equal(geom_ray_scene_all(s, &bad[i], h, 2, &n), GEOM_ERR_INVALID_ARG);
        assert_int_equal(n, 0);
    }
    /* tmin > tmax: a valid empty query */
    bad[4].tmin = 2;
    bad[4].tmax = 1;
    assert_int_equal(geom_ray_scene_closest(s, &bad[4], h, &found), GEOM_OK);
    assert_int_equal(found, 0);
    geom_ray_scene_destroy(s);
}

/* Secondary rays from every hit, leaving on either side, never re-hit their
 * own surface near t = 0, at scales 1e-4 .. 1e7 (spheres and a mesh). */
static void test_offset(void **state)
{
    int e, i;
    (void)state;
    for (e = -4; e <= 7; e++) {
        double sc = pow(10.0, e), c[3] = {3 * sc, -2 * sc, 5 * sc};
        geom_ray_scene *s = geom_ray_scene_create(NULL);
        tmesh m = icosphere(2);
        size_t k;
        for (k = 0; k < 3 * m.nv; k++) m.p[k] = m.p[k] * sc + c[k % 3] + 4 * sc;
        geom_ray_scene_add_sphere(s, c, sc, NULL);
        geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, NULL, NULL);
        built(s);
        for (i = 0; i < 400; i++) {
            double tc[3] = {c[0] + ((i & 1) ? 4 * sc : 0), c[1] + ((i & 1) ? 4 * sc : 0), c[2] + ((i & 1) ? 4 * sc : 0)};
            geom_vec3 dir = geom_vec3_make(urand() - 0.5, urand() - 0.5, urand() - 0.5);
            geom_ray r = mkray(tc[0] - 10 * sc * dir.x, tc[1] - 10 * sc * dir.y, tc[2] - 10 * sc * dir.z,
                               dir.x + (urand() - 0.5) * 0.1, dir.y + (urand() - 0.5) * 0.1, dir.z);
            geom_ray_hit h, h2;
            if (!closest(s, r, &h)) continue;
            {
                /* leave outward (reflection-like), then inward (refraction-like) */
                geom_vec3 out = geom_vec3_add(h.ng, geom_vec3_make(urand() - 0.5, urand() - 0.5, urand() - 0.5));
                geom_vec3 in = geom_vec3_neg(out), o;
                geom_ray r2;
                if (geom_vec3_dot(out, h.ng) <= 1e-3) continue;
                o = geom_ray_offset_origin(&h, out);
                r2 = mkray(o.x, o.y, o.z, out.x, out.y, out.z);
                if (closest(s, r2, &h2)) {
                    /* a hit must be on the other object, not a self-hit */
                    if (!(h2.object != h.object || h2.t > 1e-3))
                        print_error("scale 1e%d object %u t %g t2 %g prim %u/%u d.n %g\n", e, h.object, h.t, h2.t,
                                    h.prim, h2.prim, geom_vec3_dot(out, h.ng));
                    assert_true(h2.object != h.object || h2.t > 1e-3);
                }
                o = geom_ray_offset_origin(&h, in);
                r2 = mkray(o.x, o.y, o.z, in.x, in.y, in.z);
                assert_true(closest(s, r2, &h2)); /* the far side of the same closed object */
                assert_true(h2.object == h.object);
                assert_true(h2.t * geom_vec3_length(in) > 1e-3 * sc);
                assert_true(!h2.enter);
            }
        }
        geom_ray_scene_destroy(s);
        free(m.p);
        free(m.t);
    }
}

static void test_csg_instance(void **state)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double mn[3] = {-1, -1, -1}, mx[3] = {1, 1, 1}, c[3] = {0, 0, 0};
    uint32_t a, b, d, inst;
    double m[16] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 10, 0, 0, 1};
    geom_ray_hit h[8];
    size_t k;
    (void)state;
    geom_ray_scene_add_box(s, mn, mx, &a);
    geom_ray_scene_add_sphere(s, c, 0.5, &b);
    assert_int_equal(geom_ray_scene_add_csg(s, GEOM_RAY_CSG_DIFFERENCE, a, b, &d), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_instance(s, d, m, &inst), GEOM_OK);
    built(s);
    assert_int_equal(geom_ray_scene_object_count(s), 2);
    /* through the hole: box in, sphere (reversed) out, sphere in, box out */
    k = all(s, mkray(0, 0, -5, 0, 0, 1), h, 8);
    assert_int_equal(k, 4);
    assert_true(h[0].t == 4 && h[0].enter);
    assert_true(fabs(h[1].t - 4.5) < 1e-15 && !h[1].enter && h[1].ng.z > 0.99);
    assert_true(fabs(h[2].t - 5.5) < 1e-15 && h[2].enter && h[2].ng.z < -0.99);
    assert_true(h[3].t == 6 && !h[3].enter);
    /* a ray starting inside the hole */
    k = all(s, mkray(0, 0, 0, 0, 0, 1), h, 8);
    assert_int_equal(k, 2);
    assert_true(fabs(h[0].t - 0.5) < 1e-15 && h[0].enter);
    /* the instance: scaled by 2 about its origin and moved to x = 10 */
    k = all(s, mkray(10, 0, -5, 0, 0, 1), h, 8);
    assert_int_equal(k, 4);
    assert_true(fabs(h[0].t - 3) < 1e-14 && h[0].object == 1 && fabs(h[0].point.z + 2) < 1e-14);
    assert_true(fabs(h[1].t - 4) < 1e-14);
    /* union and intersection */
    {
        geom_ray_scene *s2 = geom_ray_scene_create(NULL);
        double c1[3] = {-0.5, 0, 0}, c2[3] = {0.5, 0, 0};
        uint32_t x, y, u;
        geom_ray_scene_add_sphere(s2, c1, 1, &x);
        geom_ray_scene_add_sphere(s2, c2, 1, &y);
        geom_ray_scene_add_csg(s2, GEOM_RAY_CSG_INTERSECTION, x, y, &u);
        built(s2);
        k = all(s2, mkray(-5, 0, 0, 1, 0, 0), h, 8);
        assert_int_equal(k, 2);
        assert_true(fabs(h[0].t - 4.5) < 1e-14 && fabs(h[1].t - 5.5) < 1e-14);
        geom_ray_scene_destroy(s2);
        s2 = geom_ray_scene_create(NULL);
        geom_ray_scene_add_sphere(s2, c1, 1, &x);
        geom_ray_scene_add_sphere(s2, c2, 1, &y);
        geom_ray_scene_add_csg(s2, GEOM_RAY_CSG_UNION, x, y, &u);
        built(s2);
        k = all(s2, mkray(-5, 0, 0, 1, 0, 0), h, 8);
        assert_int_equal(k, 2);
        assert_true(fabs(h[0].t - 3.5) < 1e-14 && fabs(h[1].t - 6.5) < 1e-14);
        geom_ray_scene_destroy(s2);
    }
    geom_ray_scene_destroy(s);
}

/* The exact rational sphere (surface module) against the analytic sphere. */
static void test_nurbs_sphere(void **state)
{
    geom_surface_frame fr;
    double ku[32], kv[32], pts[3 * 200], w[200];
    geom_nurbs_surface sph;
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    int i, hits = 0;
    (void)state;
    memset(&fr, 0, sizeof fr);
    fr.center[0] = 1;
    fr.center[1] = 0.5;
    fr.center[2] = -0.25;
    fr.xaxis[0] = 1;
    fr.zaxis[2] = 1;
    assert_int_equal(geom_surface_sphere(&fr, 2, ku, kv, pts, w, &sph), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_surface(s, &sph, NULL, NULL), GEOM_OK);
    built(s);
    for (i = 0; i < 300; i++) {
        geom_ray r = mkray(1 + (urand() - 0.5) * 5, 0.5 + (urand() - 0.5) * 5, -10, (urand() - 0.5) * 0.2,
                           (urand() - 0.5) * 0.2, 1);
        geom_vec3 f = geom_vec3_sub(r.origin, geom_vec3_make(1, 0.5, -0.25));
        double a = geom_vec3_dot(r.dir, r.dir), b = geom_vec3_dot(f, r.dir), cc = geom_vec3_dot(f, f) - 4;
        double disc = b * b - a * cc;
        geom_ray_hit h[8];
        size_t n = all(s, r, h, 8);
        if (disc > 1e-6) {
            double t0 = (-b - sqrt(disc)) / a, t1 = (-b + sqrt(disc)) / a;
            assert_int_equal(n, 2);
            assert_true(fabs(h[0].t - t0) < 1e-10 && fabs(h[1].t - t1) < 1e-10);
            assert_true(h[0].enter != h[1].enter);
            hits++;
        } else if (disc < -1e-6) {
            assert_int_equal(n, 0);
        }
    }
    assert_true(hits > 50);
    {
        /* exactly through both poles (collapsed patch edges) and through the seam */
        geom_ray_hit h[8];
        size_t n = all(s, mkray(1, 0.5, -10, 0, 0, 1), h, 8);
        assert_int_equal(n, 2);
        assert_true(fabs(h[0].t - 7.75) < 1e-9 && fabs(h[1].t - 11.75) < 1e-9);
        n = all(s, mkray(-10, 0.5, -0.25, 1, 0, 0), h, 8);
        assert_int_equal(n, 2);
        assert_true(fabs(h[0].t - 9) < 1e-9 && fabs(h[1].t - 13) < 1e-9);
    }
    geom_ray_scene_destroy(s);
}

static void test_implicit_volume(void **state)
{
    geom_implicit_expr *e = NULL;
    const char *txt = "x*x + y*y + z*z - 1";
    double bounds[6] = {-2, -2, -2, 2, 2, 2};
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray_hit h[8];
    size_t k;
    (void)state;
    assert_int_equal(geom_implicit_expr_compile(txt, strlen(txt), NULL, &e, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_implicit(s, e, bounds, 0, NULL), GEOM_OK);
    built(s);
    k = all(s, mkray(0.6, 0, -5, 0, 0, 1), h, 8);
    assert_int_equal(k, 2);
    assert_true(fabs(h[0].t - 4.2) < 1e-9 && h[0].enter && fabs(h[1].t - 5.8) < 1e-9 && !h[1].enter);
    assert_true(fabs(h[0].ng.x - 0.6) < 1e-9);
    /* thin feature: a slab of width 1e-6 is not skipped */
    {
        geom_implicit_expr *e2 = NULL;
        const char *t2 = "abs(x - 0.3) - 5e-7";
        geom_ray_scene *s2 = geom_ray_scene_create(NULL);
        assert_int_equal(geom_implicit_expr_compile(t2, strlen(t2), NULL, &e2, NULL), GEOM_OK);
        geom_ray_scene_add_implicit(s2, e2, bounds, 0, NULL);
        built(s2);
        k = all(s2, mkray(-1.7, 0.1, 0.2, 1, 0.01, 0), h, 8);
        assert_int_equal(k, 2);
        assert_true(fabs(h[0].t - (2.0 - 5e-7)) < 1e-9);
        geom_ray_scene_destroy(s2);
        geom_implicit_expr_destroy(e2);
    }
    /* sphere tracing with a true Lipschitz bound gives the same first hit */
    {
        geom_ray_scene *s3 = geom_ray_scene_create(NULL);
        geom_ray_hit h3;
        geom_ray_scene_add_implicit(s3, e, bounds, 4 * 1.8, NULL);
        built(s3);
        assert_true(closest(s3, mkray(0.6, 0, -5, 0, 0, 1), &h3));
        assert_true(fabs(h3.t - 4.2) < 1e-9);
        geom_ray_scene_destroy(s3);
    }
    geom_ray_scene_destroy(s);
    geom_implicit_expr_destroy(e);
    /* volume: samples of x - 0.37 on a grid: the trilinear interpolant is exact */
    {
        geom_implicit_volume_desc d;
        geom_implicit_volume *v = NULL;
        double *data;
        size_t i, j, kk;
        memset(&d, 0, sizeof d);
        d.dims[0] = d.dims[1] = d.dims[2] = 9;
        d.type = GEOM_IMPLICIT_SCALAR_F64;
        d.spacing[0] = d.spacing[1] = d.spacing[2] = 0.25;
        d.origin[0] = d.origin[1] = d.origin[2] = -1;
        assert_int_equal(geom_implicit_volume_create(&d, NULL, &v), GEOM_OK);
        data = geom_implicit_volume_data(v);
        for (kk = 0; kk < 9; kk++)
            for (j = 0; j < 9; j++)
                for (i = 0; i < 9; i++) {
                    double x = -1 + 0.25 * i, y = -1 + 0.25 * j, z = -1 + 0.25 * kk;
                    data[i + 9 * (j + 9 * kk)] = x * y + z; /* bilinear: exact in trilinear */
                }
        s = geom_ray_scene_create(NULL);
        assert_int_equal(geom_ray_scene_add_volume(s, v, 0.1, NULL), GEOM_OK);
        built(s);
        /* along z at x = 0.3, y = 0.5: x*y + z = 0.1 at z = -0.05 */
        k = all(s, mkray(0.3, 0.5, -3, 0, 0, 1), h, 8);
        assert_int_equal(k, 1);
        assert_true(fabs(h[0].t - 2.95) < 1e-12);
        assert_true(h[0].enter == 0);
        /* a diagonal ray: f(t) = (0.3 + t a)(0.5 + t b) + ... compare with brute force */
        {
            geom_ray r = mkray(-2, -1.5, -0.7, 1, 0.8, 0.2);
            double tt, prev = NAN;
            size_t roots = 0;
            for (tt = 1.0; tt <= 3.0; tt += 1e-5) {
                double x = -2 + tt, y = -1.5 + 0.8 * tt, z = -0.7 + 0.2 * tt, f;
                if (x < -1 || x > 1 || y < -1 || y > 1 || z < -1 || z > 1) { prev = NAN; continue; }
                f = x * y + z - 0.1;
                if (!isnan(prev) && (prev < 0) != (f < 0)) roots++;
                prev = f;
            }
            k = all(s, r, h, 8);
            assert_int_equal(k, roots);
        }
        geom_ray_scene_destroy(s);
        geom_implicit_volume_destroy(v);
    }
}

/* Many objects (a top-level BVH): closest hits equal the brute-force minimum
 * over the spheres' closed forms, ties to the smaller object index. */
static void test_many_objects(void **state)
{
    enum { NS = 300 };
    double c[NS][3], rad[NS];
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    double pp[3] = {0, 0, -30}, pn[3] = {0, 0, 1};
    int i, j;
    (void)state;
    for (i = 0; i < NS; i++) {
        for (j = 0; j < 3; j++) c[i][j] = urand() * 40 - 20;
        rad[i] = 0.2 + urand();
        assert_int_equal(geom_ray_scene_add_sphere(s, c[i], rad[i], NULL), GEOM_OK);
    }
    assert_int_equal(geom_ray_scene_add_plane(s, pp, pn, NULL), GEOM_OK);
    built(s);
    for (i = 0; i < 2000; i++) {
        geom_ray r = mkray(urand() * 40 - 20, urand() * 40 - 20, 25, urand() - 0.5, urand() - 0.5, -1);
        double best = INFINITY;
        int bo = -1, any = 0;
        geom_ray_hit h;
        int found = closest(s, r, &h);
        for (j = 0; j < NS; j++) {
            geom_vec3 f = geom_vec3_sub(r.origin, geom_vec3_make(c[j][0], c[j][1], c[j][2]));
            double a = geom_vec3_dot(r.dir, r.dir), b = geom_vec3_dot(f, r.dir);
            double cc = geom_vec3_dot(f, f) - rad[j] * rad[j], disc = b * b - a * cc;
            if (disc >= 0) {
                double t0 = (-b - sqrt(disc)) / a;
                if (t0 >= 0 && t0 < best) { best = t0; bo = j; }
            }
        }
        {
            double tp = (-30 - 25) / r.dir.z;
            if (tp < best) { best = tp; bo = NS; }
        }
        assert_true(found);
        assert_int_equal(h.object, bo);
        assert_true(fabs(h.t - best) < 1e-9 * (1 + best));
        assert_int_equal(geom_ray_scene_any(s, &r, &any), GEOM_OK);
        assert_true(any);
    }
    geom_ray_scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere),         cmocka_unit_test(test_sphere_far),
        cmocka_unit_test(test_plane_disk_box), cmocka_unit_test(test_quadric),
        cmocka_unit_test(test_torus),          cmocka_unit_test(test_watertight),
        cmocka_unit_test(test_triangle_single), cmocka_unit_test(test_invalid_rays),
        cmocka_unit_test(test_offset),         cmocka_unit_test(test_csg_instance),
        cmocka_unit_test(test_nurbs_sphere),   cmocka_unit_test(test_implicit_volume),
        cmocka_unit_test(test_many_objects),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
