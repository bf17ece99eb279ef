/*
 * The float (SSE) slab test of the ray module's wide (8-lane) BVH must be
 * conservative: a box the ray touches is never skipped, whatever the
 * rounding of the ray to float. Checked through the public scene queries
 * against brute force (geom_ray_triangle, the same watertight test, on
 * every triangle) and against the closed form "exactly one hit" for rays
 * from inside a closed mesh:
 *   - a closed cube of 8x8 squares a face at unit scale (box planes on
 *     float values), at a centre and half-size that are not floats, at
 *     1e6 and 1e15 (still the float test), at 1e20 (boxes beyond 2^60: the
 *     double test), and at 1e-30 (tiny, normal floats);
 *   - rays from inside aimed exactly at the grid's vertices and at edge
 *     midpoints (shared edges and vertices of triangles, and of the boxes'
 *     faces), from origins that are not floats;
 *   - rays with zero (+0 and -0) direction components lying in box face
 *     planes, rays starting on a box face, and direction components so
 *     small (1e-300) that their reciprocal is beyond the float test's range.
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

#define GRID 8

typedef struct cube {
    double c[3], h;
    double *p;
    uint32_t *t;
    size_t nv, nt;
} cube;

/* Coordinate of grid line i on axis k: every face computes it the same
 * way, so a vertex shared by faces has bit-identical coordinates. */
static double coord(const cube *q, int k, int i)
{
    return q->c[k] + q->h * (2.0 * i / GRID - 1.0);
}

/* Closed cube, outward triangles, 6 * GRID^2 * 2 triangles with duplicated
 * (identical) vertices along the face borders. */
static cube make_cube(double cx, double cy, double cz, double h)
{
    cube q;
    int f, i, j;
    q.c[0] = cx; q.c[1] = cy; q.c[2] = cz; q.h = h;
    q.nv = 0;
    q.nt = 0;
    q.p = malloc(6 * (GRID + 1) * (GRID + 1) * 3 * sizeof(double));
    q.t = malloc(6 * GRID * GRID * 2 * 3 * sizeof(uint32_t));
    for (f = 0; f < 6; f++) {
        int ax = f / 2, hi = f % 2, u = (ax + 1) % 3, v = (ax + 2) % 3;
        uint32_t base = (uint32_t)q.nv;
        for (j = 0; j <= GRID; j++)
            for (i = 0; i <= GRID; i++) {
                double *p = q.p + 3 * q.nv++;
                p[ax] = coord(&q, ax, hi ? GRID : 0);
                p[u] = coord(&q, u, i);
                p[v] = coord(&q, v, j);
            }
        for (j = 0; j < GRID; j++)
            for (i = 0; i < GRID; i++) {
                uint32_t a = base + (uint32_t)(j * (GRID + 1) + i), b = a + 1, c = a + GRID + 1, d = c + 1;
                uint32_t *t = q.t + 3 * q.nt;
                /* (u, v, ax) is right-handed: counter-clockwise in (u, v) faces +ax */
                if (hi) {
                    t[0] = a; t[1] = b; t[2] = d; t[3] = a; t[4] = d; t[5] = c;
                } else {
                    t[0] = a; t[1] = d; t[2] = b; t[3] = a; t[4] = c; t[5] = d;
                }
                q.nt += 2;
            }
    }
    return q;
}

static geom_ray_scene *scene_of(const cube *q)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray_build_options bo;
    assert_non_null(s);
    memset(&bo, 0, sizeof bo);
    bo.bvh_threads = 1;
    assert_int_equal(geom_ray_scene_add_triangles(s, q->p, q->nv, q->t, q->nt, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, &bo, NULL, NULL), GEOM_OK);
    return s;
}

/* Brute force: the closest hit over every triangle (ties: smaller index). */
static int brute(const cube *q, const geom_ray *r, double *t, uint32_t *prim)
{
    size_t i;
    int found = 0;
    for (i = 0; i < q->nt; i++) {
        geom_ray_hit h;
        const uint32_t *tv = q->t + 3 * i;
        if (!geom_ray_triangle(r, q->p + 3 * tv[0], q->p + 3 * tv[1], q->p + 3 * tv[2], &h)) continue;
        if (!found || h.t < *t) {
            *t = h.t;
            *prim = (uint32_t)i;
            found = 1;
        }
    }
    return found;
}

static int n_checked;

/* The scene's closest hit equals brute force's; from inside (inside != 0)
 * the ray crosses the closed surface exactly once. */
static void check_ray(const cube *q, const geom_ray_scene *s, const geom_ray *r, int inside)
{
    geom_ray_hit h, all[8];
    int found = 0, bf;
    double bt = 0;
    uint32_t bp = 0;
    size_t n = 0;
    assert_int_equal(geom_ray_scene_closest(s, r, &h, &found), GEOM_OK);
    bf = brute(q, r, &bt, &bp);
    if (found != bf)
        fail_msg("o (%.17g %.17g %.17g) d (%.17g %.17g %.17g): scene %s, brute force %s", r->origin.x,
                 r->origin.y, r->origin.z, r->dir.x, r->dir.y, r->dir.z, found ? "hit" : "miss",
                 bf ? "hit" : "miss");
    if (found) {
        /* same Woop arithmetic; allow rounding of a contracted expression */
        if (!(fabs(h.t - bt) <= 1e-12 * fabs(bt)))
            fail_msg("t %.17g vs brute force %.17g (prim %u vs %u)", h.t, bt, h.prim, bp);
    }
    if (inside) {
        assert_int_equal(geom_ray_scene_all(s, r, all, 8, &n), GEOM_OK);
        if (n != 1)
            fail_msg("o (%.17g %.17g %.17g) d (%.17g %.17g %.17g): %zu hits from inside, want 1", r->origin.x,
                     r->origin.y, r->origin.z, r->dir.x, r->dir.y, r->dir.z, n);
    }
    n_checked++;
}

static geom_ray ray_to(const double o[3], const double p[3])
{
    geom_ray r;
    r.origin = geom_vec3_make(o[0], o[1], o[2]);
    r.dir = geom_vec3_make(p[0] - o[0], p[1] - o[1], p[2] - o[2]);
    r.tmin = 0;
    r.tmax = INFINITY;
    return r;
}

/* Rays from a few inside origins (not floats: thirds and sevenths of the
 * half-size) to every grid vertex and every edge midpoint of the cube. */
static void cube_rays(double cx, double cy, double cz, double h)
{
    cube q = make_cube(cx, cy, cz, h);
    geom_ray_scene *s = scene_of(&q);
    const double fr[4][3] = {{0, 0, 0}, {1.0 / 3, -1.0 / 7, 2.0 / 9}, {-0.6180339887, 0.1, 0.9}, {0.99, 0.99, -0.99}};
    size_t i, oi;
    for (oi = 0; oi < 4; oi++) {
        double o[3];
        int k;
        for (k = 0; k < 3; k++) o[k] = q.c[k] + q.h * fr[oi][k];
        for (i = 0; i < q.nt; i++) {
            const uint32_t *tv = q.t + 3 * i;
            double mid[3];
            geom_ray r = ray_to(o, q.p + 3 * tv[0]); /* a vertex */
            check_ray(&q, s, &r, 1);
            for (k = 0; k < 3; k++) mid[k] = 0.5 * (q.p[3 * tv[0] + k] + q.p[3 * tv[1] + k]); /* an edge */
            r = ray_to(o, mid);
            check_ray(&q, s, &r, 1);
        }
    }
    geom_ray_scene_destroy(s);
    free(q.p);
    free(q.t);
}

static void test_unit_cube_float_planes(void **state)
{
    (void)state;
    cube_rays(0, 0, 0, 1);
}

static void test_cube_not_floats(void **state)
{
    (void)state;
    cube_rays(0.1, -0.2, 0.3, 0.7);
}

static void test_cube_huge(void **state)
{
    (void)state;
    cube_rays(1e6 + 0.1, -1e6, 3e6, 1e3 + 0.3);   /* float test, origin rounding dominant */
    cube_rays(1e15, 2e15 + 12345, -1e15, 1e12); /* float test, coordinates near 2^50 */
    cube_rays(1e20, -1e20, 1e20, 1e17);         /* boxes beyond 2^60: the double test */
}

static void test_cube_tiny(void **state)
{
    (void)state;
    cube_rays(3e-30, -1e-30, 2e-30, 1e-31);
}

/* Axis-parallel rays (zero direction components, both signs of zero)
 * along the cube's grid lines and face planes, from outside and from
 * origins on the boxes' faces; and a direction whose components are too
 * small for the float test. Compared with brute force. */
static void test_axis_parallel_and_grazing(void **state)
{
    const double centres[3][4] = {{0, 0, 0, 1}, {0.1, -0.2, 0.3, 0.7}, {1e6 + 0.1, -1e6, 3e6, 1e3 + 0.3}};
    size_t ci;
    (void)state;
    for (ci = 0; ci < 3; ci++) {
        cube q = make_cube(centres[ci][0], centres[ci][1], centres[ci][2], centres[ci][3]);
        geom_ray_scene *s = scene_of(&q);
        int ax, i, j, sgn;
        for (ax = 0; ax < 3; ax++) {
            int u = (ax + 1) % 3, v = (ax + 2) % 3;
            for (i = 0; i <= GRID; i++)
                for (j = 0; j <= GRID; j++)
                    for (sgn = 0; sgn < 2; sgn++) {
                        geom_ray r;
                        double o[3], d[3] = {0, 0, 0};
                        o[ax] = sgn ? coord(&q, ax, GRID) + 2 * q.h : coord(&q, ax, 0) - 2 * q.h;
                        o[u] = coord(&q, u, i);
                        o[v] = coord(&q, v, j);
                        d[ax] = sgn ? -1 : 1;
                        d[u] = sgn ? -0.0 : 0.0;
                        d[v] = sgn ? 0.0 : -0.0;
                        r.origin = geom_vec3_make(o[0], o[1], o[2]);
                        r.dir = geom_vec3_make(d[0], d[1], d[2]);
                        r.tmin = 0;
                        r.tmax = INFINITY;
                        check_ray(&q, s, &r, 0); /* along a grid line: a vertex or an edge */
                        /* starting on the cube's face plane (a box face), inward */
                        o[ax] = sgn ? coord(&q, ax, GRID) : coord(&q, ax, 0);
                        r.origin = geom_vec3_make(o[0], o[1], o[2]);
                        check_ray(&q, s, &r, 0);
                        /* a tiny transverse component: reciprocal beyond 2^60 */
                        d[u] = 1e-300;
                        r.dir = geom_vec3_make(d[0], d[1], d[2]);
                        check_ray(&q, s, &r, 0);
                        /* inside the face plane itself (coplanar with the face) */
                        d[ax] = 0;
                        d[u] = 1;
                        r.origin = geom_vec3_make(o[0], o[1], o[2]);
                        r.dir = geom_vec3_make(d[0], d[1], d[2]);
                        check_ray(&q, s, &r, 0);
                    }
        }
        geom_ray_scene_destroy(s);
        free(q.p);
        free(q.t);
    }
}

/* Random rays through random points of random triangles from far away
 * (origins at 1e3 sizes, not floats): the float origin's rounding is
 * larger than the cells. */
static void test_far_origins(void **state)
{
    cube q = make_cube(0.25, 0.5, -0.125, 1.0 / 3);
    geom_ray_scene *s = scene_of(&q);
    uint64_t x = 88172645463325252u;
    int it;
    (void)state;
    for (it = 0; it < 3000; it++) {
        double a, b, o[3], p[3];
        size_t ti;
        int k;
        geom_ray r;
        x ^= x << 13; x ^= x >> 7; x ^= x << 17;
        ti = (size_t)(x % q.nt);
        a = (double)((x >> 20) & 0xffff) / 65536.0;
        b = (double)((x >> 36) & 0xffff) / 65536.0 * (1 - a);
        if (it % 3 == 0) { a = 0.5; b = 0.5; } /* an edge */
        for (k = 0; k < 3; k++) {
            const uint32_t *tv = q.t + 3 * ti;
            p[k] = (1 - a - b) * q.p[3 * tv[0] + k] + a * q.p[3 * tv[1] + k] + b * q.p[3 * tv[2] + k];
            o[k] = p[k] + 1e3 * (((double)((x >> (8 * k)) & 0xff) / 255.0) - 0.5) + 1.0 / 3;
        }
        r = ray_to(o, p);
        check_ray(&q, s, &r, 0);
    }
    geom_ray_scene_destroy(s);
    free(q.p);
    free(q.t);
}

static void test_count(void **state)
{
    (void)state;
    assert_true(n_checked > 20000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_unit_cube_float_planes),
        cmocka_unit_test(test_cube_not_floats),
        cmocka_unit_test(test_cube_huge),
        cmocka_unit_test(test_cube_tiny),
        cmocka_unit_test(test_axis_parallel_and_grazing),
        cmocka_unit_test(test_far_origins),
        cmocka_unit_test(test_count),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
