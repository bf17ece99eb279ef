/*
 * scene rasterizer against closed forms: a textured quad in perspective
 * matches the analytic perspective-correct mapping (ray-plane intersection at
 * every pixel centre), an orthographic Lambertian quad is kd cos(theta)
 * everywhere with no hole (clipped on all four sides), a ground plane that
 * crosses the near plane gives the analytic depth at every pixel, the shadow
 * of a sphere on a plane under a point light covers the analytic region at
 * pixel centres away from its boundary, flat/Gouraud/Phong agree on a plane,
 * bad input is refused.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "unit/scene_testutil.h"
#include "geom/scene.h"

#define PI 3.14159265358979323846

/* Quad in the plane z = z0 over [-s, s]^2 with VERTEX uv ((x/s+1)/4+1/4, (y/s+1)/4+1/4). */
static geom_mesh *quad(double s, double z0, int uv)
{
    double p[12] = {-s, -s, z0, s, -s, z0, s, s, z0, -s, s, z0};
    uint32_t sizes[1] = {4}, idx[4] = {0, 1, 2, 3};
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, 4, p, 1, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    if (uv) {
        uint32_t id;
        assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_VERTEX, 2, &id), GEOM_OK);
        double *d = geom_mesh_channel_data(m, id);
        for (int i = 0; i < 4; i++) {
            /* the middle half of the texture: clamped borders of coarse
             * MIP levels stay away */
            d[2 * i] = (p[3 * i] / s + 1) / 4 + 0.25;
            d[2 * i + 1] = (p[3 * i + 1] / s + 1) / 4 + 0.25;
        }
    }
    return m;
}

/* Latitude-longitude sphere with exact VERTEX normals. */
static geom_mesh *sphere(geom_vec3 c, double r, int nu, int nv)
{
    size_t nvert = (size_t)(nu + 1) * (nv + 1);
    double *p = malloc(3 * nvert * sizeof(double));
    uint32_t *sizes = malloc((size_t)nu * nv * sizeof(uint32_t));
    uint32_t *idx = malloc(4 * (size_t)nu * nv * sizeof(uint32_t));
    /* poles: repeated vertices make degenerate quads; use triangles there by
     * merging indices into the pole vertex */
    for (int j = 0; j <= nv; j++)
        for (int i = 0; i <= nu; i++) {
            double th = PI * j / nv, ph = 2 * PI * i / nu;
            size_t k = (size_t)j * (nu + 1) + i;
            p[3 * k] = c.x + r * sin(th) * cos(ph);
            p[3 * k + 1] = c.y + r * sin(th) * sin(ph);
            p[3 * k + 2] = c.z + r * cos(th);
        }
    size_t nf = 0, ni = 0;
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            uint32_t a = (uint32_t)(j * (nu + 1) + i), b = a + 1, d = a + (uint32_t)nu + 1,
                     e = d + 1;
            if (j == 0) {
                sizes[nf++] = 3;
                idx[ni++] = a; idx[ni++] = d; idx[ni++] = e;
            } else if (j == nv - 1) {
                sizes[nf++] = 3;
                idx[ni++] = a; idx[ni++] = d; idx[ni++] = b;
            } else {
                sizes[nf++] = 4;
                idx[ni++] = a; idx[ni++] = d; idx[ni++] = e; idx[ni++] = b;
            }
        }
    geom_mesh *m = geom_mesh_create(NULL);
    geom_mesh_build_options o = {0};
    o.keep_orientation = 1;
    assert_int_equal(geom_mesh_build(m, nvert, p, nf, sizes, idx, &o, NULL, NULL), GEOM_OK);
    uint32_t id;
    assert_int_equal(geom_mesh_channel_add(m, "normal", GEOM_MESH_DOMAIN_VERTEX, 3, &id), GEOM_OK);
    double *n = geom_mesh_channel_data(m, id);
    const double *q = geom_mesh_cpositions(m);
    for (size_t v = 0; v < geom_mesh_n_vertices(m); v++) {
        n[3 * v] = (q[3 * v] - c.x) / r;
        n[3 * v + 1] = (q[3 * v + 1] - c.y) / r;
        n[3 * v + 2] = (q[3 * v + 2] - c.z) / r;
    }
    free(p);
    free(sizes);
    free(idx);
    return m;
}

static void test_textured_quad_perspective(void **state)
{
    (void)state;
    geom_texture *tex = uv_texture();
    geom_mesh *q = quad(1, 0, 1);
    geom_material mat;
    geom_light amb;
    geom_camera cam;
    textured_quad_view(tex, &mat, &amb, &cam);
    geom_scene_draw d = {q, NULL, 0, 7};
    geom_image out = {0};
    geom_raster_report rep;
    assert_int_equal(geom_scene_raster(&cam, &amb, 1, &mat, 1, &d, 1, NULL, &out, &rep), GEOM_OK);
    assert_int_equal(out.channels, 3);
    assert_int_equal(rep.triangles_in, 2);
    size_t checked = 0;
    double maxerr = 0;
    for (uint32_t j = 0; j < cam.height; j++)
        for (uint32_t i = 0; i < cam.width; i++) {
            geom_ray r;
            assert_int_equal(geom_scene_camera_ray(&cam, i + 0.5, j + 0.5, &r), GEOM_OK);
            const double *px = out.data + ((size_t)j * cam.width + i) * 3;
            if (!(r.dir.z < 0)) {
                assert_close(px[0], 0, 0);
                continue;
            }
            double t = -r.origin.z / r.dir.z;
            double x = r.origin.x + t * r.dir.x, y = r.origin.y + t * r.dir.y;
            if (fabs(x) > 1.02 || fabs(y) > 1.02) {
                assert_close(px[0] + px[1] + px[2], 0, 0);
                continue;
            }
            if (fabs(x) > 0.97 || fabs(y) > 0.97)
                continue;
            double u = (x + 1) / 4 + 0.25, v = (y + 1) / 4 + 0.25;
            maxerr = fmax(maxerr, fmax(fabs(px[0] - u), fabs(px[1] - v)));
            checked++;
        }
    assert_true(checked > 5000);
    if (maxerr > 2e-4)
        fail_msg("perspective-correct mapping off by %g", maxerr);
    geom_scene_image_free(&out, NULL);
    /* object AOV */
    geom_raster_options o = {0};
    o.aov = GEOM_AOV_OBJECT;
    assert_int_equal(geom_scene_raster(&cam, &amb, 1, &mat, 1, &d, 1, &o, &out, NULL), GEOM_OK);
    assert_int_equal(out.channels, 1);
    assert_close(out.data[(size_t)60 * 160 + 80], 7, 0);
    assert_close(out.data[0], -1, 0);
    geom_scene_image_free(&out, NULL);
    geom_mesh_destroy(q);
    geom_scene_texture_destroy(tex);
}

static void test_ortho_lambert_clipped(void **state)
{
    (void)state;
    geom_mesh *q = quad(10, 0, 0); /* much larger than the view: clipped on all sides */
    geom_material mat = {0};
    mat.kd = geom_vec3_make(0.25, 0.5, 0.75);
    geom_light L = {0};
    L.kind = GEOM_LIGHT_DIRECTIONAL;
    L.direction = geom_vec3_make(0.6, 0, -0.8);
    L.color = geom_vec3_make(1, 1, 1);
    geom_camera cam = {0};
    cam.eye = geom_vec3_make(0, 0, 5);
    cam.center = geom_vec3_make(0, 0, 0);
    cam.projection = GEOM_PROJECTION_ORTHOGRAPHIC;
    cam.ortho_height = 3;
    cam.width = 64;
    cam.height = 48;
    cam.samples = 4;
    for (int sh = 0; sh < 3; sh++) {
        mat.shading = (geom_shading)sh;
        geom_scene_draw d = {q, NULL, 0, 0};
        geom_image out = {0};
        geom_raster_report rep;
        geom_raster_options o = {0};
        o.shadows = 1;
        o.background = geom_vec3_make(9, 9, 9);
        assert_int_equal(geom_scene_raster(&cam, &L, 1, &mat, 1, &d, 1, &o, &out, &rep), GEOM_OK);
        assert_int_equal(rep.samples_per_pixel, 4);
        assert_true(rep.triangles_clipped >= 2);
        for (size_t k = 0; k < (size_t)64 * 48; k++) {
            assert_close(out.data[3 * k], 0.25 * 0.8, 1e-12);
            assert_close(out.data[3 * k + 2], 0.75 * 0.8, 1e-12);
        }
        geom_scene_image_free(&out, NULL);
    }
    geom_mesh_destroy(q);
}

static void test_depth_through_near_plane(void **state)
{
    (void)state;
    geom_mesh *q = quad(50, 0, 0); /* ground plane, extends behind the eye */
    geom_material mat = geom_scene_material_default();
    geom_camera cam = {0};
    cam.eye = geom_vec3_make(0, 0, 1);
    cam.center = geom_vec3_make(0, 10, 0.2);
    cam.up = geom_vec3_make(0, 0, 1);
    cam.fovy_degrees = 70;
    cam.width = 120;
    cam.height = 90;
    geom_scene_draw d = {q, NULL, 0, 0};
    geom_raster_options o = {0};
    o.aov = GEOM_AOV_DEPTH;
    geom_image out = {0};
    geom_raster_report rep;
    assert_int_equal(geom_scene_raster(&cam, NULL, 0, &mat, 1, &d, 1, &o, &out, &rep), GEOM_OK);
    geom_vec3 f;
    geom_vec3_normalize(geom_vec3_sub(cam.center, cam.eye), &f);
    size_t hits = 0;
    for (uint32_t j = 0; j < cam.height; j++)
        for (uint32_t i = 0; i < cam.width; i++) {
            geom_ray r;
            geom_scene_camera_ray(&cam, i + 0.5, j + 0.5, &r);
            double z = out.data[(size_t)j * cam.width + i];
            double t = r.dir.z < 0 ? -r.origin.z / r.dir.z : INFINITY;
            geom_vec3 p = geom_vec3_add(r.origin, geom_vec3_scale(r.dir, t));
            if (!(t < INFINITY) || fabs(p.x) > 49.9 || fabs(p.y) > 49.9) {
                if (!(t < INFINITY) || fabs(p.x) > 50.1 || fabs(p.y) > 50.1)
                    assert_true(isinf(z));
                continue;
            }
            /* exact up to the rasterizer's 1/256-pixel vertex snapping:
             * the analytic depths at the pixel centre moved by 1/256 px */
            double lo = INFINITY, hi = 0;
            for (int di = -1; di <= 1; di++)
                for (int dj = -1; dj <= 1; dj++) {
                    geom_ray r2;
                    geom_scene_camera_ray(&cam, i + 0.5 + di / 256.0, j + 0.5 + dj / 256.0, &r2);
                    double t2 = -r2.origin.z / r2.dir.z, e = t2 * geom_vec3_dot(r2.dir, f);
                    if (!(t2 > 0))
                        e = INFINITY;
                    lo = fmin(lo, e);
                    hi = fmax(hi, e);
                }
            if (!(z >= lo * (1 - 1e-9) && z <= hi * (1 + 1e-9)))
                fail_msg("pixel %u %u depth %.17g outside [%.17g, %.17g]", i, j, z, lo, hi);
            hits++;
        }
    assert_true(hits > 3000);
    geom_scene_image_free(&out, NULL);
    geom_mesh_destroy(q);
}

/* Does the segment from q to the light hit the sphere (c, r)? */
static int occluded(geom_vec3 q, geom_vec3 light, geom_vec3 c, double r)
{
    geom_vec3 d = geom_vec3_sub(light, q), oc = geom_vec3_sub(q, c);
    double a = geom_vec3_dot(d, d), b = geom_vec3_dot(oc, d), cc = geom_vec3_dot(oc, oc) - r * r;
    double disc = b * b - a * cc;
    if (disc < 0)
        return 0;
    double t = (-b - sqrt(disc)) / a;
    return t > 0 && t < 1;
}

static void test_shadow_of_sphere(void **state)
{
    (void)state;
    geom_vec3 c = geom_vec3_make(0, 0, 1), light = geom_vec3_make(1, -0.5, 3);
    double r = 0.5;
    geom_mesh *ground = quad(4, 0, 0);
    geom_mesh *ball = sphere(c, r, 128, 64);
    geom_material mat = geom_scene_material_default();
    mat.ka = geom_vec3_make(0, 0, 0);
    geom_light L = {0};
    L.kind = GEOM_LIGHT_POINT;
    L.position = light;
    L.color = geom_vec3_make(1, 1, 1);
    geom_camera cam = {0};
    cam.eye = geom_vec3_make(0, -5, 6);
    cam.center = geom_vec3_make(0, 0, 0);
    cam.up = geom_vec3_make(0, 0, 1);
    cam.fovy_degrees = 40;
    cam.width = 160;
    cam.height = 120;
    geom_scene_draw d[2] = {{ground, NULL, 0, 0}, {ball, NULL, 0, 1}};
    geom_raster_options o = {0};
    o.shadows = 1;
    o.shadow_map_size = 2048;
    geom_image out = {0}, obj = {0};
    geom_raster_report rep;
    assert_int_equal(geom_scene_raster(&cam, &L, 1, &mat, 1, d, 2, &o, &out, &rep), GEOM_OK);
    assert_int_equal(rep.shadow_maps, 6);
    o.aov = GEOM_AOV_OBJECT;
    assert_int_equal(geom_scene_raster(&cam, &L, 1, &mat, 1, d, 2, &o, &obj, NULL), GEOM_OK);
    size_t in_shadow = 0, lit = 0;
    for (uint32_t j = 0; j < cam.height; j++)
        for (uint32_t i = 0; i < cam.width; i++) {
            size_t k = (size_t)j * cam.width + i;
            if (obj.data[k] != 0)
                continue;
            geom_ray ry;
            geom_scene_camera_ray(&cam, i + 0.5, j + 0.5, &ry);
            double t = -ry.origin.z / ry.dir.z;
            geom_vec3 q = geom_vec3_add(ry.origin, geom_vec3_scale(ry.dir, t));
            /* classify robustly: the same answer for radius +-3% */
            int s0 = occluded(q, light, c, r * 0.97), s1 = occluded(q, light, c, r * 1.03);
            if (s0 != s1)
                continue;
            double v = out.data[3 * k];
            if (s0) {
                assert_close(v, 0, 0);
                in_shadow++;
            } else {
                assert_true(v > 0);
                lit++;
            }
        }
    assert_true(in_shadow > 300);
    assert_true(lit > 5000);
    geom_scene_image_free(&out, NULL);
    geom_scene_image_free(&obj, NULL);
    geom_mesh_destroy(ground);
    geom_mesh_destroy(ball);
}

static void test_bad_input(void **state)
{
    (void)state;
    geom_mesh *q = quad(1, 0, 0);
    geom_material mat = geom_scene_material_default();
    geom_camera cam = {0};
    cam.eye = geom_vec3_make(0, 0, 3);
    geom_scene_draw d = {q, NULL, 1, 0};
    geom_image out = {0};
    assert_int_equal(geom_scene_raster(&cam, NULL, 0, &mat, 1, &d, 1, NULL, &out, NULL),
                     GEOM_ERR_INVALID_ARG);
    d.material = 0;
    cam.center = cam.eye;
    assert_int_equal(geom_scene_raster(&cam, NULL, 0, &mat, 1, &d, 1, NULL, &out, NULL),
                     GEOM_ERR_DEGENERATE);
    assert_int_equal(geom_scene_raster(NULL, NULL, 0, &mat, 1, &d, 1, NULL, &out, NULL),
                     GEOM_ERR_INVALID_ARG);
    /* an empty scene is the background */
    cam.center = geom_vec3_make(0, 0, 0);
    assert_int_equal(geom_scene_raster(&cam, NULL, 0, &mat, 1, NULL, 0, NULL, &out, NULL), GEOM_OK);
    assert_close(out.data[5], 0, 0);
    geom_scene_image_free(&out, NULL);
    geom_scene_image_free(NULL, NULL);
    geom_mesh_destroy(q);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_textured_quad_perspective),
        cmocka_unit_test(test_ortho_lambert_clipped),
        cmocka_unit_test(test_depth_through_near_plane),
        cmocka_unit_test(test_shadow_of_sphere),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
