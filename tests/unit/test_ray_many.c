/*
 * geom_ray_scene_any_many and geom_ray_scene_all_many against the single-ray
 * functions they replace in a loop: found[i] equal to geom_ray_scene_any's,
 * each compressed row of hits equal bit for bit (same order, every field) to
 * geom_ray_scene_all's, on every representation (a triangle mesh, a mesh
 * with shading normals, a subdivision surface, the analytic shapes (sphere,
 * box, oriented box, torus, capped quadric, plane, disk, triangle, polygon:
 * enough objects for the top-level BVH), a NURBS sphere, implicit
 * expressions (interval method and sphere tracing), a sampled volume, CSG
 * difference / union / intersection, instances and a group), and the
 * any/all answers consistent with each other (a ray has an any-hit exactly
 * when its all-hit row is not empty) and with the closed form of the
 * sphere. Rays: random through the scene, and every eighth a special one
 * (+-0 components, tmin > tmax, a short [tmin, tmax], NaN origin, Inf or
 * zero direction, NaN tmin / tmax: GEOM_ERR_INVALID_ARG, an empty row, the
 * other rays answered). The caller-sized output: cap 0 (hits NULL), a cap
 * inside a row and the exact cap (GEOM_ERR_LIMIT with complete offsets and
 * the first cap hits written, GEOM_OK at the exact size); batch sizes 0,
 * 1 and odd; an empty scene, an unbuilt scene and NULL arguments.
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
#include "geom/subdiv.h"
#include "unit/ray_testutil.h"

static uint64_t rng = 0x2b7e151628aed2a6ull;
static double urand(void)
{
    return ray_urand(&rng);
}

#define MAXH 256

/* n rays from a box of half-size 3*size about c towards points of the box
 * of half-size size; every eighth special (see the file comment). */
static geom_ray *make_rays(const double c[3], double size, size_t n)
{
    geom_ray *rays = malloc((n ? n : 1) * sizeof *rays);
    size_t i;
    for (i = 0; i < n; i++) {
        double a[3], b[3];
        int k;
        geom_ray r;
        for (k = 0; k < 3; k++) {
            a[k] = c[k] + size * 6 * (urand() - 0.5);
            b[k] = c[k] + size * 2 * (urand() - 0.5);
        }
        r = mkray(a[0], a[1], a[2], b[0] - a[0], b[1] - a[1], b[2] - a[2]);
        if (i % 8 == 3) {
            switch ((i / 8) % 10) {
            case 0: r.dir.x = 0.0; break;
            case 1: r.dir.y = -0.0; r.dir.z = 0.0; break;
            case 2: r.tmin = 2; r.tmax = 1; break; /* empty, valid */
            case 3: r.tmin = 0.3; r.tmax = 0.7; break;
            case 4: r.origin.y = NAN; break;
            case 5: r.dir.z = INFINITY; break;
            case 6: r.dir.x = r.dir.y = r.dir.z = 0; break;
            case 7: r.tmin = NAN; break;
            case 8: r.tmax = NAN; break;
            default: /* from the centre: starts inside closed objects */
                r.origin = geom_vec3_make(c[0], c[1], c[2]);
                break;
            }
        }
        rays[i] = r;
    }
    return rays;
}

/* The batches against the single-ray functions. Returns the number of rays
 * with a hit; *nhits the total hit count. */
static size_t check_many(const geom_ray_scene *s, const geom_ray *rays, size_t n, size_t *nhits)
{
    int *fa = malloc((n ? n : 1) * sizeof *fa);
    size_t *off = malloc((n + 1) * sizeof *off), *off2 = malloc((n + 1) * sizeof *off2);
    size_t i, total = 0, cnt = 7, cnt2 = 7, nhit = 0;
    geom_ray_hit *hb, h1[MAXH];
    int invalid = 0;
    geom_status st, sa;
    for (i = 0; i < n; i++) invalid |= geom_ray_check(&rays[i]) != GEOM_OK;
    memset(fa, 0x55, (n ? n : 1) * sizeof *fa);
    sa = geom_ray_scene_any_many(s, rays, n, fa);
    assert_int_equal(sa, invalid ? GEOM_ERR_INVALID_ARG : GEOM_OK);
    /* sizes first (cap 0, no buffer), then the exact size */
    memset(off, 0x55, (n + 1) * sizeof *off);
    st = geom_ray_scene_all_many(s, rays, n, off, NULL, 0, &cnt);
    assert_int_equal(off[0], 0);
    assert_int_equal(off[n], cnt);
    if (cnt > 0) assert_int_equal(st, GEOM_ERR_LIMIT);
    else assert_int_equal(st, invalid ? GEOM_ERR_INVALID_ARG : GEOM_OK);
    hb = malloc((cnt ? cnt : 1) * sizeof *hb);
    st = geom_ray_scene_all_many(s, rays, n, off2, hb, cnt, &cnt2);
    assert_int_equal(st, invalid ? GEOM_ERR_INVALID_ARG : GEOM_OK);
    assert_int_equal(cnt2, cnt);
    assert_memory_equal(off, off2, (n + 1) * sizeof *off);
    for (i = 0; i < n; i++) {
        int f1 = 7;
        size_t k1 = 7, j;
        geom_status s1 = geom_ray_scene_any(s, &rays[i], &f1), s2;
        assert_true(s1 == GEOM_OK || s1 == GEOM_ERR_INVALID_ARG);
        assert_int_equal(s1 == GEOM_ERR_INVALID_ARG, geom_ray_check(&rays[i]) != GEOM_OK);
        assert_int_equal(fa[i], f1);
        s2 = geom_ray_scene_all(s, &rays[i], h1, MAXH, &k1);
        assert_int_equal(s2, s1);
        assert_true(k1 <= MAXH);
        assert_true(off[i] <= off[i + 1]);
        if (off[i + 1] - off[i] != k1)
            fail_msg("ray %zu o (%.17g %.17g %.17g) d (%.17g %.17g %.17g): batch %zu hits, single %zu", i,
                     rays[i].origin.x, rays[i].origin.y, rays[i].origin.z, rays[i].dir.x, rays[i].dir.y,
                     rays[i].dir.z, off[i + 1] - off[i], k1);
        for (j = 0; j < k1; j++) assert_true(ray_same_hit(&hb[off[i] + j], &h1[j]));
        /* any and all agree */
        assert_int_equal(f1, k1 > 0);
        nhit += f1 != 0;
        total += k1;
    }
    assert_int_equal(total, cnt);
    /* a cap inside the output: LIMIT, offsets complete, the first cap hits */
    if (cnt > 1) {
        size_t cap = cnt / 2 + 1, cnt3 = 0;
        geom_ray_hit *hc = malloc(cap * sizeof *hc);
        memset(off2, 0, (n + 1) * sizeof *off2);
        assert_int_equal(geom_ray_scene_all_many(s, rays, n, off2, hc, cap, &cnt3),
                         cap < cnt ? GEOM_ERR_LIMIT : (invalid ? GEOM_ERR_INVALID_ARG : GEOM_OK));
        assert_int_equal(cnt3, cnt);
        assert_memory_equal(off, off2, (n + 1) * sizeof *off);
        for (i = 0; i < cap; i++) assert_true(ray_same_hit(&hc[i], &hb[i]));
        free(hc);
    }
    free(hb);
    free(fa);
    free(off);
    free(off2);
    if (nhits) *nhits = cnt;
    return nhit;
}

/* check_many on n rays and on small batches at odd offsets. */
static size_t check_scene(const geom_ray_scene *s, const double c[3], double size, size_t n, const char *what)
{
    geom_ray *rays = make_rays(c, size, n);
    size_t nhits = 0, nhit = check_many(s, rays, n, &nhits);
    print_message("%s: %zu rays, %zu with a hit, %zu hits\n", what, n, nhit, nhits);
    assert_true(nhit > n / 8);
    check_many(s, rays + 5, 0, NULL);
    check_many(s, rays + 3, 1, NULL);
    check_many(s, rays + 11, 7, NULL);
    check_many(s, rays + 20, 9, NULL);
    free(rays);
    return nhit;
}

static geom_ray_scene *new_scene(void)
{
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    assert_non_null(s);
    return s;
}

static void build(geom_ray_scene *s)
{
    assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
}

static void test_meshes(void **state)
{
    tmesh m = icosphere(3);
    geom_ray_scene *s = new_scene();
    const double c[3] = {0, 0, 0};
    (void)state;
    assert_int_equal(geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, NULL, NULL), GEOM_OK);
    build(s);
    check_scene(s, c, 1, 3000, "icosphere");
    /* rays from inside at every vertex and edge midpoint: one hit each,
     * through the batch too (watertight, no double hits) */
    {
        size_t nin = m.nv + 3 * m.nt, i, cnt = 0;
        geom_ray *rays = malloc(nin * sizeof *rays);
        size_t *off = malloc((nin + 1) * sizeof *off);
        geom_ray_hit *hb = malloc(nin * sizeof *hb);
        for (i = 0; i < nin; i++) {
            double tgt[3];
            tmesh_target(&m, i, tgt);
            rays[i] = mkray(0.01, -0.02, 0.005, tgt[0] - 0.01, tgt[1] + 0.02, tgt[2] - 0.005);
        }
        assert_int_equal(geom_ray_scene_all_many(s, rays, nin, off, hb, nin, &cnt), GEOM_OK);
        assert_int_equal(cnt, nin);
        for (i = 0; i < nin; i++) assert_int_equal(off[i + 1] - off[i], 1);
        check_many(s, rays, nin, NULL);
        free(rays);
        free(off);
        free(hb);
    }
    geom_ray_scene_destroy(s);
    /* with shading normals, moved: a mesh under a transform */
    {
        double mx[16] = {1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1};
        const double c2[3] = {5, 0, 0};
        uint32_t id;
        s = new_scene();
        assert_int_equal(geom_ray_scene_add_triangles(s, m.p, m.nv, m.t, m.nt, m.p, &id), GEOM_OK);
        assert_int_equal(geom_ray_scene_set_transform(s, id, mx), GEOM_OK);
        build(s);
        check_scene(s, c2, 1.5, 1500, "transformed icosphere with normals");
        geom_ray_scene_destroy(s);
    }
    free(m.p);
    free(m.t);
}

static void test_subdiv(void **state)
{
    static const double p[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                 -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
    static const uint32_t sz[6] = {4, 4, 4, 4, 4, 4};
    static const uint32_t f[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    geom_mesh *gm = geom_mesh_create(NULL);
    geom_ray_scene *s = new_scene();
    const double c[3] = {0, 0, 0};
    (void)state;
    assert_int_equal(geom_mesh_build(gm, 8, p, 6, sz, f, NULL, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_subdiv(s, gm, GEOM_SUBDIV_CATMULL_CLARK, 3, NULL, NULL), GEOM_OK);
    build(s);
    check_scene(s, c, 1, 1000, "catmull-clark cube");
    geom_ray_scene_destroy(s);
    geom_mesh_destroy(gm);
}

/* Every analytic shape (more than 8 objects: the top-level BVH), and the
 * sphere's closed form through the batch. */
static void test_analytic(void **state)
{
    geom_ray_scene *s = new_scene();
    const double c[3] = {0, 0, 0};
    double q[10], clip[6] = {-0.3, -0.3, -1, 0.3, 0.3, 1}, rp[1] = {0.25};
    const double sc[3] = {0.5, 0.4, 0.3}, bmin[3] = {-1, -0.2, 0.4}, bmax[3] = {-0.5, 0.3, 0.9};
    const double ocen[3] = {0.6, -0.6, -0.5}, oax[9] = {1, 1, 0, -1, 1, 0, 0, 0, 1}, ohalf[3] = {0.2, 0.1, 0.3};
    const double pp[3] = {0, 0, -2.5}, pn[3] = {0, 0.1, 1}, dc[3] = {0, 2, 0}, dn[3] = {0, -1, 0.2};
    const double tri[9] = {-1, -1, 1.5, 1, -1, 1.5, 0, 1, 1.6};
    const double poly[15] = {1.2, 0, 0, 1.6, 0.3, 0, 1.7, 0.8, 0.1, 1.3, 1.0, 0.1, 1.1, 0.5, 0};
    double mt[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1.5, 0.5, 0, 1};
    uint32_t tor;
    (void)state;
    assert_int_equal(geom_ray_scene_add_sphere(s, sc, 0.35, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_box(s, bmin, bmax, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_obox(s, ocen, oax, ohalf, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_torus(s, 0.5, 0.15, &tor), GEOM_OK);
    assert_int_equal(geom_ray_scene_set_transform(s, tor, mt), GEOM_OK);
    assert_int_equal(geom_ray_quadric_make(GEOM_RAY_QUADRIC_CYLINDER, rp, q), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_quadric(s, q, clip, 1, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_plane(s, pp, pn, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_disk(s, dc, dn, 0.7, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_triangle(s, tri, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_polygon(s, poly, 5, NULL), GEOM_OK);
    build(s);
    check_scene(s, c, 1.2, 3000, "analytic shapes");
    geom_ray_scene_destroy(s);
    /* one sphere: the batch's rows are the closed-form roots */
    {
        geom_ray *rays;
        size_t n = 500, i, cnt = 0, *off = malloc((n + 1) * sizeof *off), two = 0;
        geom_ray_hit *hb = malloc(2 * n * sizeof *hb);
        s = new_scene();
        assert_int_equal(geom_ray_scene_add_sphere(s, sc, 0.35, NULL), GEOM_OK);
        build(s);
        rays = malloc(n * sizeof *rays);
        for (i = 0; i < n; i++) {
            double a[3], b[3];
            int k;
            for (k = 0; k < 3; k++) {
                a[k] = sc[k] + (i % 5 == 0 ? 0.3 : 2.0) * (urand() - 0.5); /* some from inside */
                b[k] = sc[k] + 0.8 * (urand() - 0.5);
            }
            rays[i] = mkray(a[0], a[1], a[2], b[0] - a[0], b[1] - a[1], b[2] - a[2]);
        }
        assert_int_equal(geom_ray_scene_all_many(s, rays, n, off, hb, 2 * n, &cnt), GEOM_OK);
        for (i = 0; i < n; i++) {
            geom_vec3 f = geom_vec3_sub(rays[i].origin, geom_vec3_make(sc[0], sc[1], sc[2])), d = rays[i].dir;
            double a = geom_vec3_dot(d, d), b = geom_vec3_dot(f, d), cc = geom_vec3_dot(f, f) - 0.35 * 0.35;
            double disc = b * b - a * cc;
            size_t k = off[i + 1] - off[i];
            if (disc > 1e-9 * a) {
                double t0 = (-b - sqrt(disc)) / a, t1 = (-b + sqrt(disc)) / a;
                size_t expect = (t0 >= 0) + (t1 >= 0);
                if (fabs(t0) < 1e-9) continue; /* origin on the sphere */
                assert_int_equal(k, expect);
                if (expect == 2) {
                    assert_true(fabs(hb[off[i]].t - t0) < 1e-12 * (1 + fabs(t0)) && hb[off[i]].enter);
                    assert_true(fabs(hb[off[i] + 1].t - t1) < 1e-12 * (1 + fabs(t1)) && !hb[off[i] + 1].enter);
                    two++;
                }
            } else if (disc < -1e-9 * a) {
                assert_int_equal(k, 0);
            }
        }
        assert_true(two > n / 10);
        free(rays);
        free(off);
        free(hb);
        geom_ray_scene_destroy(s);
    }
}

static void test_nurbs(void **state)
{
    geom_surface_frame fr;
    double ku[32], kv[32], pts[3 * 200], w[200];
    geom_nurbs_surface sph;
    geom_ray_scene *s = new_scene();
    const double c[3] = {1, 0.5, -0.25};
    (void)state;
    memset(&fr, 0, sizeof fr);
    memcpy(fr.center, c, sizeof c);
    fr.xaxis[0] = 1;
    fr.zaxis[2] = 1;
    assert_int_equal(geom_surface_sphere(&fr, 2, ku, kv, pts, w, &sph), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_surface(s, &sph, NULL, NULL), GEOM_OK);
    build(s);
    check_scene(s, c, 2, 400, "NURBS sphere");
    geom_ray_scene_destroy(s);
}

static void test_implicit_volume(void **state)
{
    const char *txt = "x*x + y*y + z*z - 1", *gyr = "sin(4*x)*cos(4*y) + sin(4*y)*cos(4*z) + sin(4*z)*cos(4*x)";
    const double bounds[6] = {-1.5, -1.5, -1.5, 1.5, 1.5, 1.5}, c[3] = {0, 0, 0};
    geom_implicit_expr *e = NULL, *g = NULL;
    geom_ray_scene *s;
    (void)state;
    assert_int_equal(geom_implicit_expr_compile(txt, strlen(txt), NULL, &e, NULL), GEOM_OK);
    assert_int_equal(geom_implicit_expr_compile(gyr, strlen(gyr), NULL, &g, NULL), GEOM_OK);
    s = new_scene();
    assert_int_equal(geom_ray_scene_add_implicit(s, e, bounds, 0, NULL), GEOM_OK);
    build(s);
    check_scene(s, c, 1, 400, "implicit sphere (intervals)");
    geom_ray_scene_destroy(s);
    s = new_scene();
    /* |grad| <= 4 * 2 * sqrt(3) for the gyroid; sphere tracing for any */
    assert_int_equal(geom_ray_scene_add_implicit(s, g, bounds, 8 * 1.7321, NULL), GEOM_OK);
    build(s);
    check_scene(s, c, 1.5, 200, "gyroid (sphere tracing + intervals)");
    geom_ray_scene_destroy(s);
    geom_implicit_expr_destroy(e);
    geom_implicit_expr_destroy(g);
    {
        geom_implicit_volume_desc d;
        geom_implicit_volume *v = NULL;
        double *data;
        size_t i, j, k;
        memset(&d, 0, sizeof d);
        d.dims[0] = d.dims[1] = d.dims[2] = 17;
        d.type = GEOM_IMPLICIT_SCALAR_F64;
        d.spacing[0] = d.spacing[1] = d.spacing[2] = 0.125;
        d.origin[0] = d.origin[1] = d.origin[2] = -1;
        assert_int_equal(geom_implicit_volume_create(&d, NULL, &v), GEOM_OK);
        data = geom_implicit_volume_data(v);
        for (k = 0; k < 17; k++)
            for (j = 0; j < 17; j++)
                for (i = 0; i < 17; i++) {
                    double x = -1 + 0.125 * i, y = -1 + 0.125 * j, z = -1 + 0.125 * k;
                    data[i + 17 * (j + 17 * k)] = x * x + y * y + z * z + 0.3 * x * y * z;
                }
        s = new_scene();
        assert_int_equal(geom_ray_scene_add_volume(s, v, 0.5, NULL), GEOM_OK);
        build(s);
        check_scene(s, c, 1, 1000, "volume");
        geom_ray_scene_destroy(s);
        geom_implicit_volume_destroy(v);
    }
}

static void test_csg_instances(void **state)
{
    geom_ray_scene *s = new_scene();
    const double mn[3] = {-1, -1, -1}, mx[3] = {1, 1, 1}, o[3] = {0, 0, 0}, c1[3] = {-0.5, 0, 0},
                 c2[3] = {0.5, 0, 0}, c[3] = {2, 0, 0};
    double m[16] = {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 4, 0, 0, 1};
    double m2[16] = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 2, 1.5, 0, 1};
    uint32_t a, b, d, x, y, u, x2, y2, in, grp[2], inst;
    (void)state;
    geom_ray_scene_add_box(s, mn, mx, &a);
    geom_ray_scene_add_sphere(s, o, 0.6, &b);
    assert_int_equal(geom_ray_scene_add_csg(s, GEOM_RAY_CSG_DIFFERENCE, a, b, &d), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_instance(s, d, m, &inst), GEOM_OK);
    geom_ray_scene_add_sphere(s, c1, 0.7, &x);
    geom_ray_scene_add_sphere(s, c2, 0.7, &y);
    assert_int_equal(geom_ray_scene_add_csg(s, GEOM_RAY_CSG_UNION, x, y, &u), GEOM_OK);
    assert_int_equal(geom_ray_scene_set_transform(s, u, m2), GEOM_OK);
    geom_ray_scene_add_sphere(s, c1, 0.7, &x2);
    geom_ray_scene_add_sphere(s, c2, 0.7, &y2);
    assert_int_equal(geom_ray_scene_add_csg(s, GEOM_RAY_CSG_INTERSECTION, x2, y2, &in), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_instance(s, in, m, &grp[0]), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_instance(s, grp[0], m2, &grp[1]), GEOM_OK);
    assert_int_equal(geom_ray_scene_add_group(s, grp, 2, NULL), GEOM_OK);
    build(s);
    check_scene(s, c, 2.5, 3000, "CSG, instances, group");
    geom_ray_scene_destroy(s);
}

static void test_empty_unbuilt_args(void **state)
{
    geom_ray_scene *s = new_scene();
    const double c[3] = {0, 0, 0};
    geom_ray *rays = make_rays(c, 1, 64);
    size_t off[65], cnt = 9, i;
    int found[64];
    geom_ray_hit h[4];
    (void)state;
    /* unbuilt: every answer empty */
    memset(found, 0x55, sizeof found);
    assert_int_equal(geom_ray_scene_any_many(s, rays, 64, found), GEOM_ERR_INVALID_ARG);
    for (i = 0; i < 64; i++) assert_int_equal(found[i], 0);
    memset(off, 0x55, sizeof off);
    assert_int_equal(geom_ray_scene_all_many(s, rays, 64, off, h, 4, &cnt), GEOM_ERR_INVALID_ARG);
    assert_int_equal(cnt, 0);
    for (i = 0; i <= 64; i++) assert_int_equal(off[i], 0);
    /* empty scene, built: nothing hit, invalid rays still reported */
    build(s);
    check_many(s, rays, 64, &cnt);
    assert_int_equal(cnt, 0);
    /* NULL arguments */
    assert_int_equal(geom_ray_scene_any_many(NULL, rays, 1, found), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_any_many(s, NULL, 1, found), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_any_many(s, rays, 1, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_any_many(s, NULL, 0, NULL), GEOM_OK);
    assert_int_equal(geom_ray_scene_all_many(NULL, rays, 1, off, h, 4, &cnt), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_all_many(s, NULL, 1, off, h, 4, &cnt), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_all_many(s, rays, 1, NULL, h, 4, &cnt), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_all_many(s, rays, 1, off, NULL, 4, &cnt), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_ray_scene_all_many(s, rays, 1, off, h, 4, NULL), GEOM_ERR_INVALID_ARG);
    cnt = 9;
    assert_int_equal(geom_ray_scene_all_many(s, NULL, 0, off, NULL, 0, &cnt), GEOM_OK);
    assert_int_equal(cnt, 0);
    assert_int_equal(off[0], 0);
    free(rays);
    geom_ray_scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_meshes),         cmocka_unit_test(test_subdiv),
        cmocka_unit_test(test_analytic),       cmocka_unit_test(test_nurbs),
        cmocka_unit_test(test_implicit_volume), cmocka_unit_test(test_csg_instances),
        cmocka_unit_test(test_empty_unbuilt_args),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
