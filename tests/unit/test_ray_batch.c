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
 *     single mesh: one ray at a time); NULL arguments and an unbuilt scene;
 *   - coherent batches, which the AVX2 path traces as packets of eight
 *     (checked with the internal count geom__ray_scene_packets: the test
 *     fails when no packet is made on an AVX2 CPU): camera rays at an
 *     icosphere (at unit scale and at 1e3) and at a random soup in front of
 *     it, with per-ray [tmin, tmax] (pruning some rays of a packet, empty
 *     ranges) and NaN / Inf / zero-direction rays mixed in; rays aimed
 *     exactly at the vertices and edge midpoints of a flat grid, from above
 *     (direction components exactly zero in a column) and at a grazing angle
 *     (1e-3 and 1e-6 rad); the camera behind the mesh looking away.
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

/* Internal (ray/ray_internal.h): force every mesh of s onto one path;
 * count the runs of eight rays closest_many traces as packets. */
int geom__ray_scene_simd(geom_ray_scene *s, int isa);
size_t geom__ray_scene_packets(const geom_ray_scene *s, const geom_ray *rays, size_t n);

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

/* Camera rays, row by row (w x h), from eye e towards c over a field of
 * half width fov (in units of the distance), every ray with [tmin, tmax]
 * = [0, inf]. */
static size_t camera_rays(const double e[3], const double c[3], int w, int h, double fov, geom_ray *rays)
{
    double f[3], up[3] = {0, 1, 0}, rt[3], u2[3], l = 0, lr, lu;
    size_t n = 0;
    int x, y, k;
    for (k = 0; k < 3; k++) f[k] = c[k] - e[k], l += f[k] * f[k];
    l = sqrt(l);
    if (fabs(f[1]) > 0.9 * l) up[1] = 0, up[2] = 1;
    rt[0] = f[1] * up[2] - f[2] * up[1];
    rt[1] = f[2] * up[0] - f[0] * up[2];
    rt[2] = f[0] * up[1] - f[1] * up[0];
    u2[0] = rt[1] * f[2] - rt[2] * f[1];
    u2[1] = rt[2] * f[0] - rt[0] * f[2];
    u2[2] = rt[0] * f[1] - rt[1] * f[0];
    lr = sqrt(rt[0] * rt[0] + rt[1] * rt[1] + rt[2] * rt[2]);
    lu = sqrt(u2[0] * u2[0] + u2[1] * u2[1] + u2[2] * u2[2]);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            double sx = (x + 0.5) / w * 2 - 1, sy = (y + 0.5) / h * 2 - 1, d[3];
            for (k = 0; k < 3; k++) d[k] = f[k] + fov * l * (sx * rt[k] / lr + sy * u2[k] / lu);
            rays[n++] = mkray(e[0], e[1], e[2], d[0], d[1], d[2]);
        }
    return n;
}

/* Special rays mixed into a coherent batch: per-ray ranges cutting inside
 * the hit distances (dist: about the eye's distance to the mesh), empty
 * ranges, and (invalid) NaN / Inf / zero-direction rays. */
static void mix_special(geom_ray *rays, size_t n, double dist, int invalid)
{
    size_t i;
    for (i = 0; i < n; i++) {
        geom_ray *r = &rays[i];
        double dl = sqrt(r->dir.x * r->dir.x + r->dir.y * r->dir.y + r->dir.z * r->dir.z);
        if (i % 11 == 3) { r->tmin = (dist - 0.3) / dl; r->tmax = (dist + 0.2) / dl; }
        else if (i % 13 == 5) r->tmin = (dist + 0.05) / dl;  /* past the front: the back or nothing */
        else if (i % 17 == 7) r->tmax = (dist - 0.05) / dl;  /* before the front */
        else if (i % 19 == 2) { r->tmin = 2; r->tmax = 1; } /* empty */
        else if (invalid && i % 23 == 4) r->origin.y = NAN;
        else if (invalid && i % 29 == 6) r->dir.z = INFINITY;
        else if (invalid && i % 31 == 8) r->dir.x = r->dir.y = r->dir.z = 0;
    }
}

/* The batch on both paths against single rays and brute force, and the
 * number of packets it makes on the AVX2 path (at least minpk there). */
static void packet_check(geom_ray_scene *s, const tmesh *m, const geom_ray *rays, size_t n, int invalid,
                         size_t minpk, const char *what)
{
    size_t npk, nhit;
    int avx;
    geom__ray_scene_simd(s, 1);
    avx = geom__ray_scene_simd(s, 1) == 1;
    npk = geom__ray_scene_packets(s, rays, n);
    print_message("%s: %zu rays, %zu packets of eight on the %s path\n", what, n, npk, avx ? "AVX2" : "SSE2");
    if (avx && ray_cpu_avx2()) assert_true(npk >= minpk);
    else assert_int_equal(npk, 0);
    nhit = check_batch(s, m, rays, n, invalid);
    print_message("    %zu with a hit\n", nhit);
    assert_true(nhit > 0);
}

static void test_packets_camera(void **state)
{
    const double offs[2] = {0, 1e3};
    int oi;
    (void)state;
    for (oi = 0; oi < 2; oi++) {
        const double off = offs[oi];
        tmesh m = icosphere(4);
        geom_ray_scene *s = geom_ray_scene_create(NULL);
        geom_ray *rays = malloc(64 * 48 * sizeof *rays);
        const double eye[3] = {off + 0.4, off + 0.3, off + 3}, ctr[3] = {off, off, off};
        const double back[3] = {off + 0.1, off - 0.2, off + 0.1}, away[3] = {off + 0.3, off - 0.6, off + 4};
        size_t i, n;
        for (i = 0; i < 3 * m.nv; i++) m.p[i] += off;
        assert_int_equal(geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, NULL, NULL), GEOM_OK);
        assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
        n = camera_rays(eye, ctr, 64, 48, 0.45, rays);
        packet_check(s, &m, rays, n, 0, n / 8 / 2, "camera at an icosphere");
        mix_special(rays, n, 2.1, 1);
        packet_check(s, &m, rays, n, 1, n / 8 / 4, "camera at an icosphere, special rays mixed in");
        n = camera_rays(back, away, 64, 48, 0.3, rays); /* from inside, looking at the back */
        packet_check(s, &m, rays, n, 0, n / 8 / 2, "camera inside an icosphere");
        free(rays);
        free(m.p);
        free(m.t);
        geom_ray_scene_destroy(s);
    }
}

/* A random soup of small triangles in front of an icosphere: many leaves
 * and overlapping boxes on each packet's way. */
static void test_packets_soup(void **state)
{
    tmesh sp = icosphere(3), m;
    const size_t nsoup = 3000;
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray *rays = malloc(64 * 64 * sizeof *rays);
    const double eye[3] = {0.2, 0.1, 4}, ctr[3] = {0, 0, 0};
    size_t i, n;
    (void)state;
    m.nv = sp.nv + 3 * nsoup;
    m.nt = sp.nt + nsoup;
    m.p = malloc(3 * m.nv * sizeof *m.p);
    m.t = malloc(3 * m.nt * sizeof *m.t);
    memcpy(m.p, sp.p, 3 * sp.nv * sizeof *m.p);
    memcpy(m.t, sp.t, 3 * sp.nt * sizeof *m.t);
    for (i = 0; i < nsoup; i++) {
        double c[3] = {2.4 * (urand() - 0.5), 2.4 * (urand() - 0.5), 1.2 + 1.5 * urand()};
        int a, k;
        for (a = 0; a < 3; a++) {
            for (k = 0; k < 3; k++) m.p[3 * (sp.nv + 3 * i + (size_t)a) + (size_t)k] = c[k] + 0.08 * (urand() - 0.5);
            m.t[3 * (sp.nt + i) + (size_t)a] = (uint32_t)(sp.nv + 3 * i + (size_t)a);
        }
    }
    assert_int_equal(geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    n = camera_rays(eye, ctr, 64, 64, 0.35, rays);
    packet_check(s, &m, rays, n, 0, n / 8 / 2, "camera at a soup in front of an icosphere");
    mix_special(rays, n, 1.5, 1);
    packet_check(s, &m, rays, n, 1, n / 8 / 4, "the same, special rays mixed in");
    free(rays);
    free(m.p);
    free(m.t);
    free(sp.p);
    free(sp.t);
    geom_ray_scene_destroy(s);
}

/* A flat grid of (g + 1)^2 vertices over [0, 1]^2 in z = 0, two triangles
 * a cell (diagonals alternating). */
static tmesh grid_mesh(int g)
{
    tmesh m;
    int x, y;
    size_t nt = 0;
    m.nv = (size_t)(g + 1) * (size_t)(g + 1);
    m.nt = 2 * (size_t)g * (size_t)g;
    m.p = malloc(3 * m.nv * sizeof *m.p);
    m.t = malloc(3 * m.nt * sizeof *m.t);
    for (y = 0; y <= g; y++)
        for (x = 0; x <= g; x++) {
            double *p = m.p + 3 * ((size_t)y * (size_t)(g + 1) + (size_t)x);
            p[0] = (double)x / g;
            p[1] = (double)y / g;
            p[2] = 0;
        }
    for (y = 0; y < g; y++)
        for (x = 0; x < g; x++) {
            uint32_t a = (uint32_t)(y * (g + 1) + x), b = a + 1, c = a + (uint32_t)(g + 1), d = c + 1;
            uint32_t *t = m.t + 3 * nt;
            if ((x + y) % 2) {
                t[0] = a; t[1] = b; t[2] = d; t[3] = a; t[4] = d; t[5] = c;
            } else {
                t[0] = a; t[1] = b; t[2] = c; t[3] = b; t[4] = d; t[5] = c;
            }
            nt += 2;
        }
    return m;
}

/* Rays from e aimed exactly at the grid's vertices and the midpoints of
 * its x edges in the block of rows y0 .. y0 + rows - 1, columns x0 .. x0 +
 * cols - 1, row by row (neighbours: coherent). */
static size_t grid_rays(int g, const double e[3], int x0, int y0, int cols, int rows, geom_ray *rays)
{
    size_t n = 0;
    int x, y, h;
    for (y = y0; y < y0 + rows; y++)
        for (x = x0; x < x0 + cols; x++)
            for (h = 0; h < 2 && (h == 0 || x + 1 < x0 + cols); h++) {
                double t[3] = {((double)x + 0.5 * h) / g, (double)y / g, 0};
                rays[n++] = mkray(e[0], e[1], e[2], t[0] - e[0], t[1] - e[1], t[2] - e[2]);
            }
    return n;
}

static void test_packets_grid(void **state)
{
    const int g = 96;
    tmesh m = grid_mesh(g);
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray *rays = malloc((24 * 48 + 2 * (g + 1)) * sizeof *rays);
    /* from above (the column x = 0.5: direction x exactly 0), grazing at
     * about 1e-3 and 1e-6 rad, from below */
    const double eyes[4][3] = {{0.5, 0.5, 1}, {0.5, -1, 1.5e-3}, {0.45, -1, 1.5e-6}, {0.52, 0.47, -0.8}};
    const char *what[4] = {"grid vertices from above", "grid vertices at 1e-3 rad", "grid vertices at 1e-6 rad",
                           "grid vertices from below"};
    int e;
    size_t n;
    (void)state;
    assert_int_equal(geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    for (e = 0; e < 4; e++) {
        n = grid_rays(g, eyes[e], 40, 38, 24, 24, rays);
        packet_check(s, &m, rays, n, 0, n / 8 / 4, what[e]);
    }
    /* along the row y = 0.5 at grazing angles: direction y exactly 0 in
     * every ray (packets of the decoding node test) */
    for (e = 0; e < 3; e++) {
        const double ez[3] = {1.5e-3, 1.5e-6, 0.3};
        const double eye[3] = {-0.7, 0.5, ez[e]};
        n = grid_rays(g, eye, 0, g / 2, g + 1, 1, rays);
        packet_check(s, &m, rays, n, 0, n / 8 / 2, "a grid row along its direction");
    }
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
        cmocka_unit_test(test_packets_camera),
        cmocka_unit_test(test_packets_soup),
        cmocka_unit_test(test_packets_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
