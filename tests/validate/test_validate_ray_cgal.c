/*
 * ray against CGAL's exact do_intersect(Ray_3, Triangle_3) (through the shim,
 * kernel Simple_cartesian<Gmpzf>: every predicate exact), on rays aimed
 * exactly at triangle vertices and edges. Coordinates are small integers and
 * dyadic fractions, so every ray passes exactly through its target point and
 * the exact predicate is decisive:
 *  - single triangles, with directions whose dominant component is a power
 *    of two (the Woop-Benthin-Wald shear is then exact too): hit/miss equals
 *    CGAL's on every ray aimed inside or outside the triangle; on a ray
 *    through an edge or a vertex CGAL says hit and libgeom hits or not by its
 *    edge-ownership rule, never hitting where CGAL misses; a ray in the
 *    triangle's plane is a miss for libgeom (documented), a hit for CGAL;
 *  - a closed triangulated cube (integer vertices, alternating diagonals) and
 *    rays from inside it through each vertex, edge midpoint and face centre,
 *    with arbitrary directions (inexact shear): exactly one hit per ray, on a
 *    triangle CGAL says the ray meets, while CGAL counts every triangle
 *    incident to the target (2 for an edge, the valence for a vertex).
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
#include "geom_validate.h"

static geom_ray mkray(const double o[3], const double d[3])
{
    geom_ray r;
    r.origin = geom_vec3_make(o[0], o[1], o[2]);
    r.dir = geom_vec3_make(d[0], d[1], d[2]);
    r.tmin = 0;
    r.tmax = INFINITY;
    return r;
}

/* Target point of kind k on triangle (a, b, c) with integer weights over 4:
 * 0..2 vertices, 3..5 edge midpoints, 6 interior, 7..9 outside (a vertex
 * reflected through the opposite edge's midpoint). */
static int target(int k, const double *a, const double *b, const double *c, double p[3])
{
    const double *v[3] = {a, b, c};
    int i;
    for (i = 0; i < 3; i++) {
        if (k < 3) p[i] = v[k][i];
        else if (k < 6) p[i] = 0.5 * (v[k - 3][i] + v[(k - 2) % 3][i]);
        else if (k == 6) p[i] = 0.25 * v[0][i] + 0.25 * v[1][i] + 0.5 * v[2][i];
        else p[i] = v[(k - 6) % 3][i] + v[(k - 5) % 3][i] - v[k - 7][i];
    }
    return k < 6 ? 1 : (k == 6 ? 0 : -1); /* 1 boundary, 0 inside, -1 outside */
}

static void test_single_triangles(void **state)
{
    size_t n = 0, agree = 0, boundary = 0, owned = 0, coplanar = 0;
    int it, k, s, ax;
    uint64_t g = 0x2545f4914f6cdd1dull;
    (void)state;
    for (it = 0; it < 400; it++) {
        double v[9], p[3];
        for (k = 0; k < 9; k++) {
            g ^= g << 13; g ^= g >> 7; g ^= g << 17;
            v[k] = (double)((int)(g % 33) - 16) * 0.5; /* halves in [-8, 8] */
        }
        if (gv_ray_triangle((double[3]){0, 0, 100}, (double[3]){0, 0, -1}, v, v + 3, v + 6) == GV_SIGN_ERROR)
            continue; /* collinear */
        for (k = 0; k < 10; k++) {
            int kind = target(k, v, v + 3, v + 6, p);
            for (ax = 0; ax < 3; ax++)
                for (s = -1; s <= 1; s += 2) {
                    double d[3], o[3];
                    geom_ray r;
                    geom_ray_hit h;
                    int ex, ours, j;
                    /* dominant component +-32 along ax, the others small integers */
                    for (j = 0; j < 3; j++) {
                        g ^= g << 13; g ^= g >> 7; g ^= g << 17;
                        d[j] = j == ax ? 32.0 * s : (double)((int)(g % 31) - 15);
                        o[j] = p[j] - d[j]; /* exact: the ray passes through p at t = 1 */
                    }
                    r = mkray(o, d);
                    ex = gv_ray_triangle(o, d, v, v + 3, v + 6);
                    assert_true(ex == 0 || ex == 1);
                    ours = geom_ray_triangle(&r, v, v + 3, v + 6, &h);
                    n++;
                    if (kind == 1) {
                        /* a ray in the triangle's plane: CGAL 1, ours 0 (skip) */
                        double e1[3], e2[3], nrm[3];
                        for (j = 0; j < 3; j++) { e1[j] = v[3 + j] - v[j]; e2[j] = v[6 + j] - v[j]; }
                        nrm[0] = e1[1] * e2[2] - e1[2] * e2[1];
                        nrm[1] = e1[2] * e2[0] - e1[0] * e2[2];
                        nrm[2] = e1[0] * e2[1] - e1[1] * e2[0];
                        if (nrm[0] * d[0] + nrm[1] * d[1] + nrm[2] * d[2] == 0) {
                            assert_int_equal(ours, 0);
                            coplanar++;
                            continue;
                        }
                        assert_int_equal(ex, 1);
                        boundary++;
                        owned += (size_t)ours;
                    } else {
                        double e1[3], e2[3], dn;
                        for (j = 0; j < 3; j++) { e1[j] = v[3 + j] - v[j]; e2[j] = v[6 + j] - v[j]; }
                        dn = (e1[1] * e2[2] - e1[2] * e2[1]) * d[0] + (e1[2] * e2[0] - e1[0] * e2[2]) * d[1] +
                             (e1[0] * e2[1] - e1[1] * e2[0]) * d[2];
                        if (dn == 0) {
                            assert_int_equal(ours, 0);
                            coplanar++;
                            continue;
                        }
                        if (ours != ex)
                            fail_msg("triangle %d target %d: libgeom %d, CGAL %d", it, k, ours, ex);
                        assert_int_equal(ex, kind == 0);
                        agree++;
                        if (ours) assert_true(fabs(h.t - 1) <= fmax(h.t_error, 1e-15));
                    }
                }
        }
    }
    printf("single triangles: %zu rays; %zu through an inside or outside point, all agreeing with CGAL; "
           "%zu through an edge or vertex (CGAL: hit), %zu of them owned by the triangle; %zu in the "
           "triangle's plane (CGAL: hit, libgeom: miss)\n",
           n, agree, boundary, owned, coplanar);
    assert_int_equal(agree + boundary + coplanar, n);
    assert_true(boundary > 1000);
    assert_true(owned > 0 && owned < boundary);
}

/* Closed cube [-8, 8]^3, each face an n x n grid of squares split along
 * alternating diagonals; outward winding. */
typedef struct cube {
    double *p;
    uint32_t *t;
    size_t nv, nt;
} cube;

static cube make_cube(int n)
{
    cube c;
    size_t cap = (size_t)6 * (n + 1) * (n + 1);
    int f, i, j;
    c.p = malloc(cap * 3 * sizeof(double));
    c.t = malloc((size_t)6 * n * n * 2 * 3 * sizeof(uint32_t));
    c.nv = 0;
    c.nt = 0;
    for (f = 0; f < 6; f++) {
        int axis = f / 2, sgn = f % 2 ? 1 : -1, u = (axis + 1) % 3, w = (axis + 2) % 3;
        uint32_t base = (uint32_t)c.nv;
        for (j = 0; j <= n; j++)
            for (i = 0; i <= n; i++) {
                double q[3];
                q[axis] = 8.0 * sgn;
                q[u] = -8 + 16.0 * i / n;
                q[w] = -8 + 16.0 * j / n;
                /* the same point on two faces: reuse the vertex */
                {
                    size_t e, found = c.nv;
                    for (e = 0; e < c.nv; e++)
                        if (c.p[3 * e] == q[0] && c.p[3 * e + 1] == q[1] && c.p[3 * e + 2] == q[2]) {
                            found = e;
                            break;
                        }
                    if (found == c.nv) {
                        memcpy(c.p + 3 * c.nv, q, sizeof q);
                        c.nv++;
                    }
                    (void)base;
                }
            }
        for (j = 0; j < n; j++)
            for (i = 0; i < n; i++) {
                uint32_t id[4];
                int cr, corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                for (cr = 0; cr < 4; cr++) {
                    double q[3];
                    size_t e;
                    q[axis] = 8.0 * sgn;
                    q[u] = -8 + 16.0 * (i + corner[cr][0]) / n;
                    q[w] = -8 + 16.0 * (j + corner[cr][1]) / n;
                    for (e = 0; e < c.nv; e++)
                        if (c.p[3 * e] == q[0] && c.p[3 * e + 1] == q[1] && c.p[3 * e + 2] == q[2]) break;
                    id[cr] = (uint32_t)e;
                }
                /* (u, w, axis) is right-handed: counter-clockwise in (u, w) faces +axis */
                if (sgn < 0) { uint32_t t = id[1]; id[1] = id[3]; id[3] = t; }
                if ((i + j) % 2) {
                    uint32_t t3[6] = {id[0], id[1], id[2], id[0], id[2], id[3]};
                    memcpy(c.t + 3 * c.nt, t3, sizeof t3);
                } else {
                    uint32_t t3[6] = {id[0], id[1], id[3], id[1], id[2], id[3]};
                    memcpy(c.t + 3 * c.nt, t3, sizeof t3);
                }
                c.nt += 2;
            }
    }
    return c;
}

static void test_closed_cube(void **state)
{
    static const double origins[][3] = {{0, 0, 0}, {1, 2, 3}, {-3.5, 0.25, 5}, {7, -7, 7},
                                        {0.125, -6.5, 2.75}, {-7.75, 7.5, -0.5}, {3, 3, 3}};
    cube c = make_cube(4);
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    size_t no, ti, nrays = 0, maxcgal = 0;
    (void)state;
    assert_int_equal(geom_ray_scene_add_triangles(s, c.p, c.nv, c.t, c.nt, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
    for (no = 0; no < sizeof origins / sizeof origins[0]; no++)
        for (ti = 0; ti < c.nt; ti++) {
            const double *a = c.p + 3 * c.t[3 * ti], *b = c.p + 3 * c.t[3 * ti + 1],
                         *cc = c.p + 3 * c.t[3 * ti + 2];
            int k;
            for (k = 0; k < 7; k++) {
                double p[3], d[3];
                geom_ray r;
                geom_ray_hit hits[8];
                size_t nh = 0, j, ncgal = 0;
                int kind = target(k, a, b, cc, p);
                for (j = 0; j < 3; j++) d[j] = p[j] - origins[no][j]; /* exact (dyadic) */
                r = mkray(origins[no], d);
                assert_int_equal(geom_ray_scene_all(s, &r, hits, 8, &nh), GEOM_OK);
                if (nh != 1)
                    fail_msg("origin %zu, triangle %zu, target %d: %zu hits", no, ti, k, nh);
                assert_int_equal(gv_ray_triangle(origins[no], d, c.p + 3 * c.t[3 * hits[0].prim],
                                                 c.p + 3 * c.t[3 * hits[0].prim + 1],
                                                 c.p + 3 * c.t[3 * hits[0].prim + 2]),
                                 1);
                assert_false(hits[0].enter);
                /* The cube is convex: a ray from inside meets it only at its exit point p,
                 * so only triangles whose box holds p can meet it (the exact test is
                 * asked for those). */
                for (j = 0; j < c.nt; j++) {
                    int ax, in = 1;
                    for (ax = 0; ax < 3 && in; ax++) {
                        double x0 = c.p[3 * c.t[3 * j] + ax], x1 = c.p[3 * c.t[3 * j + 1] + ax],
                               x2 = c.p[3 * c.t[3 * j + 2] + ax];
                        in = p[ax] >= fmin(x0, fmin(x1, x2)) && p[ax] <= fmax(x0, fmax(x1, x2));
                    }
                    if (in)
                        ncgal += (size_t)(gv_ray_triangle(origins[no], d, c.p + 3 * c.t[3 * j],
                                                          c.p + 3 * c.t[3 * j + 1],
                                                          c.p + 3 * c.t[3 * j + 2]) == 1);
                }
                if (kind == 1) assert_true(ncgal >= 2);
                if (kind == 0) assert_true(ncgal == 1);
                if (ncgal > maxcgal) maxcgal = ncgal;
                nrays++;
            }
        }
    printf("closed cube (%zu triangles): %zu rays from inside through vertices, edge midpoints and "
           "interior points: one hit each; CGAL meets up to %zu triangles on one ray\n",
           c.nt, nrays, maxcgal);
    geom_ray_scene_destroy(s);
    free(c.p);
    free(c.t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_single_triangles),
        cmocka_unit_test(test_closed_cube),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
