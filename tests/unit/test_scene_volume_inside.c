/*
 * Sampled volumes whose inside is above the isovalue (a CT scan: dense
 * inside, air around): geom_implicit_volume_detect_inside finds the side
 * from the boundary samples (the counts checked by hand); the ray module's
 * volume honours it (normals outward, d.n < 0 on rays from outside;
 * geom_ray_scene_all gives enter then leave; inside "below" on the same
 * volume gives the reverse); an inside other than 0 or 1 is refused; the
 * scene shapes carry it, and geom_scene_tessellate's mesh has a positive
 * signed volume equal to geom_iso_extract's with inside above (the same
 * orientation as geom-iso), and close to the sphere's.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "geom/iso.h"
#include "geom/scene.h"

#define N 21 /* samples per axis, spacing 0.25, centre at 2.5: radius 1.5 sphere */

/* 1000 - 100 |p - c|^2: dense (high) inside, iso 775 is |p - c| = 1.5. */
static geom_implicit_volume *ct_volume(void)
{
    geom_implicit_grid g;
    memset(&g, 0, sizeof g);
    g.dims[0] = g.dims[1] = g.dims[2] = N;
    g.type = GEOM_IMPLICIT_SCALAR_F64;
    g.spacing[0] = g.spacing[1] = g.spacing[2] = 0.25;
    geom_implicit_volume *v = NULL;
    assert_int_equal(geom_implicit_volume_create(&g, NULL, &v), GEOM_OK);
    double *d = geom_implicit_volume_data(v);
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                double x = 0.25 * i - 2.5, y = 0.25 * j - 2.5, z = 0.25 * k - 2.5;
                d[i + N * (j + N * k)] = 1000 - 100 * (x * x + y * y + z * z);
            }
    return v;
}

static double mesh_signed_volume(const geom_mesh *m)
{
    size_t ni = 0, nf = geom_mesh_n_faces(m);
    assert_int_equal(geom_mesh_to_soup(m, NULL, NULL, &ni), GEOM_OK);
    uint32_t *sizes = test_malloc((nf + 1) * sizeof *sizes), *idx = test_malloc((ni + 1) * sizeof *idx);
    assert_int_equal(geom_mesh_to_soup(m, sizes, idx, &ni), GEOM_OK);
    const double *p = geom_mesh_cpositions(m);
    double vol = 0;
    size_t at = 0;
    for (size_t f = 0; f < nf && at < ni; f++) {
        const double *a = p + 3 * idx[at];
        for (uint32_t c = 1; c + 1 < sizes[f]; c++) {
            const double *b = p + 3 * idx[at + c], *e = p + 3 * idx[at + c + 1];
            vol += (a[0] * (b[1] * e[2] - b[2] * e[1]) - a[1] * (b[0] * e[2] - b[2] * e[0]) +
                    a[2] * (b[0] * e[1] - b[1] * e[0])) / 6;
        }
        at += sizes[f];
    }
    test_free(sizes);
    test_free(idx);
    return vol;
}

static void test_detect(void **state)
{
    (void)state;
    geom_implicit_volume *v = ct_volume();
    int above = -1;
    size_t below = 0, total = 0;
    assert_int_equal(geom_implicit_volume_detect_inside(v, 775, &above, &below, &total), GEOM_OK);
    assert_int_equal(total, (size_t)(N * N * N - (N - 2) * (N - 2) * (N - 2)));
    assert_int_equal(below, total); /* every face sample is at distance >= 2.5 > 1.5 */
    assert_int_equal(above, 1);
    /* the same volume as a distance-like field: iso above every sample */
    assert_int_equal(geom_implicit_volume_detect_inside(v, 1001, &above, &below, &total), GEOM_OK);
    assert_int_equal(above, 1);
    assert_int_equal(geom_implicit_volume_detect_inside(v, -1e9, &above, &below, NULL), GEOM_OK);
    assert_int_equal(above, 0);
    assert_int_equal(below, 0);
    assert_int_equal(geom_implicit_volume_detect_inside(v, NAN, &above, NULL, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_implicit_volume_detect_inside(NULL, 1, &above, NULL, NULL), GEOM_ERR_INVALID_ARG);
    geom_implicit_volume_destroy(v);
}

static void test_rays(void **state)
{
    (void)state;
    geom_implicit_volume *v = ct_volume();
    for (int side = 0; side < 2; side++) {
        geom_ray_scene *s = geom_ray_scene_create(NULL);
        geom_ray_volume_options o = {side};
        assert_int_equal(geom_ray_scene_add_volume_opt(s, v, 775, &o, NULL), GEOM_OK);
        assert_int_equal(geom_ray_scene_build(s, NULL, NULL, NULL), GEOM_OK);
        for (int r = 0; r < 64; r++) {
            /* from 5 away from the centre, toward points near it */
            double th = 0.7 * r, ph = 0.3 + 0.05 * r;
            geom_vec3 u = geom_vec3_make(cos(th) * sin(ph), sin(th) * sin(ph), cos(ph));
            geom_ray ray;
            ray.origin = geom_vec3_make(2.5 + 5 * u.x, 2.5 + 5 * u.y, 2.5 + 5 * u.z);
            ray.dir = geom_vec3_make(-u.x + 0.01 * (r % 5), -u.y, -u.z);
            ray.tmin = 0;
            ray.tmax = INFINITY;
            geom_ray_hit h[4];
            size_t n = 0;
            int found = 0;
            assert_int_equal(geom_ray_scene_closest(s, &ray, h, &found), GEOM_OK);
            assert_true(found);
            double dn = geom_vec3_dot(h[0].ng, ray.dir) / geom_vec3_length(ray.dir);
            if (side == 1)
                assert_true(dn < -0.9); /* outward: against a ray from outside */
            else
                assert_true(dn > 0.9);
            assert_int_equal(h[0].enter, side == 1);
            assert_int_equal(geom_ray_scene_all(s, &ray, h, 4, &n), GEOM_OK);
            assert_int_equal(n, 2);
            assert_int_equal(h[0].enter, side == 1);
            assert_int_equal(h[1].enter, side != 1);
        }
        geom_ray_scene_destroy(s);
    }
    geom_ray_scene *s = geom_ray_scene_create(NULL);
    geom_ray_volume_options bad = {2};
    assert_int_equal(geom_ray_scene_add_volume_opt(s, v, 775, &bad, NULL), GEOM_ERR_INVALID_ARG);
    bad.inside = -1;
    assert_int_equal(geom_ray_scene_add_volume_opt(s, v, 775, &bad, NULL), GEOM_ERR_INVALID_ARG);
    geom_ray_scene_destroy(s);
    geom_implicit_volume_destroy(v);
}

static void test_export_matches_iso(void **state)
{
    (void)state;
    geom_implicit_volume *v = ct_volume();
    geom_ray_scene *rs = geom_ray_scene_create(NULL);
    geom_ray_volume_options o = {1};
    assert_int_equal(geom_ray_scene_add_volume_opt(rs, v, 775, &o, NULL), GEOM_OK);
    geom_scene_shapes *sh = NULL;
    assert_int_equal(geom_scene_shapes_from_ray(rs, &sh, NULL), GEOM_OK);
    assert_int_equal(geom_scene_shapes_count(sh), 1);
    const geom_shape *shape = geom_scene_shapes_get(sh, 0);
    assert_int_equal(shape->kind, GEOM_SHAPE_VOLUME);
    assert_int_equal(shape->inside, 1);
    geom_tess_request rq;
    memset(&rq, 0, sizeof rq);
    rq.tol = 1e-3;
    rq.attributes = GEOM_NEEDS_NORMAL;
    geom_mesh *m = geom_mesh_create(NULL);
    geom_tess_info info;
    assert_int_equal(geom_scene_tessellate(shape, &rq, m, &info, NULL), GEOM_OK);
    double vs = mesh_signed_volume(m);
    double sphere = 4.0 / 3.0 * 3.14159265358979323846 * 1.5 * 1.5 * 1.5;
    assert_true(vs > 0);
    assert_true(fabs(vs - sphere) < 0.03 * sphere);
    /* geom-iso's extraction of the volume itself (its grid, inside above) */
    geom_iso_grid g;
    assert_int_equal(geom_iso_grid_from_volume(v, &g), GEOM_OK);
    geom_iso_options io;
    memset(&io, 0, sizeof io);
    io.iso = 775;
    io.inside = GEOM_ISO_INSIDE_ABOVE;
    geom_iso_surface surf;
    memset(&surf, 0, sizeof surf);
    assert_int_equal(geom_iso_extract_grid(&g, &io, &surf, NULL), GEOM_OK);
    assert_true(surf.report.signed_volume > 0);
    assert_true(fabs(vs - surf.report.signed_volume) < 0.02 * surf.report.signed_volume);
    geom_iso_surface_free(&surf);
    geom_mesh_destroy(m);
    geom_scene_shapes_destroy(sh);
    geom_ray_scene_destroy(rs);
    geom_implicit_volume_destroy(v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_detect),
        cmocka_unit_test(test_rays),
        cmocka_unit_test(test_export_matches_iso),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
