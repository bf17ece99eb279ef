/*
 * scene: camera rays and projection agree with each other and with the
 * gluLookAt/gluPerspective matrices, textures (MIP pyramid averages, exact
 * bilinear lookups, wrap and clamp, gradients), local shading against
 * closed forms (Lambert, Blinn-Phong and Phong highlights, ambient,
 * cool-to-warm, bump and normal maps), material needs.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "unit/test_util.h"
#include "geom/scene.h"

#define M_PI 3.14159265358979323846

static void test_camera_ray_project(void **state)
{
    (void)state;
    geom_camera c = {0};
    c.eye = geom_vec3_make(1, 2, 3);
    c.center = geom_vec3_make(0, 0, 0);
    c.width = 200;
    c.height = 100;
    c.fovy_degrees = 60;
    for (int proj = 0; proj < 2; proj++) {
        c.projection = proj ? GEOM_PROJECTION_ORTHOGRAPHIC : GEOM_PROJECTION_PERSPECTIVE;
        c.ortho_height = 3;
        for (double x = 0.5; x < 200; x += 37.25) {
            for (double y = 0.5; y < 100; y += 23.5) {
                geom_ray r;
                assert_int_equal(geom_scene_camera_ray(&c, x, y, &r), GEOM_OK);
                geom_vec3 p = geom_vec3_add(r.origin, geom_vec3_scale(r.dir, 2.5));
                double q[3];
                assert_int_equal(geom_scene_camera_project(&c, p, q), GEOM_OK);
                assert_close(q[0], x, 1e-9);
                assert_close(q[1], y, 1e-9);
                /* and the OpenGL matrices put p on the same pixel */
                geom_mat4 view, pr;
                assert_int_equal(geom_scene_camera_matrices(&c, 0.1, 100, &view, &pr), GEOM_OK);
                geom_vec4 h = geom_mat4_mul_vec4(geom_mat4_mul(pr, view),
                                                 geom_vec4_make(p.x, p.y, p.z, 1));
                assert_close((h.x / h.w + 1) * 0.5 * 200, x, 1e-9);
                assert_close((1 - h.y / h.w) * 0.5 * 100, y, 1e-9);
            }
        }
    }
    /* centre ray is the view direction */
    c.projection = GEOM_PROJECTION_PERSPECTIVE;
    geom_ray r;
    assert_int_equal(geom_scene_camera_ray(&c, 100, 50, &r), GEOM_OK);
    double l = sqrt(14.0);
    assert_close(r.dir.x, -1 / l, 1e-15);
    assert_close(r.dir.z, -3 / l, 1e-15);
    /* pixel size: 2 d tan(30 deg) / 100 */
    assert_close(geom_scene_camera_pixel_size(&c, 10), 20 * tan(M_PI / 6) / 100, 1e-15);
    /* pixel tolerance: nearest depth of the box */
    {
        geom_camera k = {0};
        k.eye = geom_vec3_make(0, 0, 0);
        k.center = geom_vec3_make(0, 0, -1);
        k.fovy_degrees = 60;
        k.width = k.height = 100;
        geom_aabb b = {{-0.5, -0.5, -12}, {0.5, 0.5, -10}};
        int vis = -1;
        double tol = geom_scene_pixel_tolerance(&k, b, 0.5, &vis);
        assert_int_equal(vis, 1);
        assert_close(tol, 0.5 * 20 * tan(M_PI / 6) / 100, 1e-15);
        geom_aabb behind = {{-0.5, -0.5, 10}, {0.5, 0.5, 12}};
        tol = geom_scene_pixel_tolerance(&k, behind, 0.5, &vis);
        assert_int_equal(vis, 0);
        assert_close(tol, 8 * 0.5 * 20 * tan(M_PI / 6) / 100, 1e-15); /* 10 away */
        geom_aabb aside = {{50, -0.5, -12}, {51, 0.5, -10}};
        geom_scene_pixel_tolerance(&k, aside, 0.5, &vis);
        assert_int_equal(vis, 0);
    }
    /* degenerate cameras */
    geom_camera bad = c;
    bad.center = bad.eye;
    assert_int_equal(geom_scene_camera_ray(&bad, 1, 1, &r), GEOM_ERR_DEGENERATE);
    bad = c;
    bad.up = geom_vec3_make(-1, -2, -3);
    assert_int_equal(geom_scene_camera_ray(&bad, 1, 1, &r), GEOM_ERR_DEGENERATE);
    bad = c;
    bad.fovy_degrees = 180;
    assert_int_equal(geom_scene_camera_ray(&bad, 1, 1, &r), GEOM_ERR_DOMAIN);
}

static geom_texture *make_tex(uint32_t w, uint32_t h, uint32_t ch, geom_wrap wrap,
                              double (*f)(uint32_t x, uint32_t y, uint32_t c))
{
    geom_image img = {0};
    assert_int_equal(geom_scene_image_init(&img, w, h, ch, NULL), GEOM_OK);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            for (uint32_t c = 0; c < ch; c++)
                img.data[((size_t)y * w + x) * ch + c] = f(x, y, c);
    geom_texture *t = NULL;
    assert_int_equal(geom_scene_texture_create(&img, wrap, NULL, &t), GEOM_OK);
    geom_scene_image_free(&img, NULL);
    return t;
}

/* Texel value = its centre's (u, v): linear data, reproduced exactly by
 * bilinear lookup and by every MIP level of a power-of-two texture. */
static double uv_of(uint32_t x, uint32_t y, uint32_t c)
{
    return c == 0 ? (x + 0.5) / 64.0 : 1.0 - (y + 0.5) / 32.0;
}

static double checker(uint32_t x, uint32_t y, uint32_t c)
{
    (void)c;
    return (double)((x + y) & 1);
}

static void test_texture(void **state)
{
    (void)state;
    geom_texture *t = make_tex(64, 32, 2, GEOM_WRAP_CLAMP, uv_of);
    assert_int_equal(geom_scene_texture_levels(t), 7);
    double out[2];
    for (double u = 0.2; u < 0.8; u += 0.0737) {
        for (double v = 0.2; v < 0.8; v += 0.0611) {
            for (double fp = 0; fp < 0.2; fp += 0.013) {
                geom_scene_texture_sample(t, u, v, fp, out);
                /* levels up to 3 (8x4) keep these points off the clamped
                 * border half-texels; coarser ones average toward 0.5 */
                double tol = fp * 64 > 4 ? 0.35 : 1e-12;
                assert_close(out[0], u, tol);
                assert_close(out[1], v, tol);
            }
        }
    }
    double du, dv;
    geom_scene_texture_gradient(t, 0.4, 0.6, &du, &dv);
    assert_close(du, 1, 1e-12);
    assert_close(dv, 0, 1e-12); /* channel 0 is u only */
    /* clamp: outside the image the edge texel centres' values */
    geom_scene_texture_sample(t, -3, 7, 0, out);
    assert_close(out[0], 0.5 / 64, 1e-15);
    assert_close(out[1], 1 - 0.5 / 32, 1e-15);
    geom_scene_texture_sample(t, NAN, 0.5, 0, out);
    assert_false(isnan(out[0]));
    geom_scene_texture_destroy(t);

    /* checker: the 1x1 level is the mean 0.5; level 0 at a texel centre is the texel */
    t = make_tex(16, 16, 1, GEOM_WRAP_REPEAT, checker);
    assert_int_equal(geom_scene_texture_levels(t), 5);
    geom_scene_texture_sample(t, 0.3, 0.3, 100, out);
    assert_close(out[0], 0.5, 1e-15);
    geom_scene_texture_sample(t, 0.5 / 16, 1 - 0.5 / 16, 0, out);
    assert_close(out[0], 0, 1e-15);
    geom_scene_texture_sample(t, 1.5 / 16 + 3, 1 - 0.5 / 16 - 2, 0, out); /* repeat */
    assert_close(out[0], 1, 1e-12);
    /* half-way between texel centres: the average, across the wrap too */
    geom_scene_texture_sample(t, 0, 1 - 0.5 / 16, 0, out);
    assert_close(out[0], 0.5, 1e-15);
    geom_scene_texture_destroy(t);
    geom_scene_texture_destroy(NULL);

    /* odd sizes and 1-wide images still reach 1x1 */
    t = make_tex(5, 1, 1, GEOM_WRAP_REPEAT, checker);
    assert_int_equal(geom_scene_texture_levels(t), 3);
    geom_scene_texture_sample(t, 0.5, 0.5, 10, out);
    assert_close(out[0], 0.4, 1e-12); /* box filter keeps the mean 2/5 */
    geom_scene_texture_destroy(t);

    geom_image img = {0};
    geom_texture *bad = NULL;
    assert_int_equal(geom_scene_texture_create(&img, GEOM_WRAP_REPEAT, NULL, &bad), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_scene_image_init(&img, 2, 2, 1, NULL), GEOM_OK);
    img.data[3] = NAN;
    assert_int_equal(geom_scene_texture_create(&img, GEOM_WRAP_REPEAT, NULL, &bad), GEOM_ERR_INVALID_ARG);
    assert_null(bad);
    geom_scene_image_free(&img, NULL);
}

static void test_shade_closed_forms(void **state)
{
    (void)state;
    geom_material m = geom_scene_material_default();
    m.kd = geom_vec3_make(0.5, 0.6, 0.7);
    m.ka = geom_vec3_make(0.1, 0.2, 0.3);
    m.ks = geom_vec3_make(0.25, 0.25, 0.25);
    m.ns = 20;
    geom_light L[2] = {{0}};
    L[0].kind = GEOM_LIGHT_POINT;
    L[0].position = geom_vec3_make(3, 0, 4);
    L[0].color = geom_vec3_make(1, 1, 1);
    L[1].kind = GEOM_LIGHT_AMBIENT;
    L[1].color = geom_vec3_make(0.5, 0.5, 0.5);
    geom_shade_point sp = {0};
    sp.n = geom_vec3_make(0, 0, 1);
    sp.v = geom_vec3_make(0, 0.6, 0.8);
    geom_vec3 c;
    geom_scene_shade(&m, L, 2, NULL, &sp, sp.n, &c);
    /* l = (0.6, 0, 0.8); h = (0.6, 0.6, 1.6)/|.| ; n.h = 1.6/sqrt(3.28) */
    double nl = 0.8, nh = 1.6 / sqrt(0.36 + 0.36 + 2.56);
    assert_close(c.x, 0.05 + 0.5 * nl + 0.25 * pow(nh, 20), 1e-15);
    assert_close(c.z, 0.15 + 0.7 * nl + 0.25 * pow(nh, 20), 1e-15);
    /* Phong: r = 2(n.l)n - l = (-0.6, 0, 0.8); r.v = 0.64 */
    m.specular = GEOM_SPECULAR_PHONG;
    geom_scene_shade(&m, L, 2, NULL, &sp, sp.n, &c);
    assert_close(c.x, 0.05 + 0.5 * nl + 0.25 * pow(0.64, 20), 1e-15);
    /* in shadow: ambient only */
    double vis[2] = {0, 0};
    geom_scene_shade(&m, L, 2, vis, &sp, sp.n, &c);
    assert_close(c.y, 0.1, 1e-15);
    /* back face seen from behind is lit as its flipped side (two-sided) */
    sp.v = geom_vec3_make(0, 0.6, -0.8);
    L[0].position = geom_vec3_make(3, 0, -4);
    geom_scene_shade(&m, L, 1, NULL, &sp, sp.n, &c);
    assert_close(c.x, 0.5 * nl + 0.25 * pow(0.64, 20), 1e-15);
    /* cool-to-warm: n.l = 1 gives k_warm = (0.4,0.4,0) + 0.6 kd */
    m = geom_scene_material_default();
    m.style = GEOM_STYLE_COOL_TO_WARM;
    sp.v = geom_vec3_make(0, 0, 1);
    L[0].position = geom_vec3_make(0, 0, 5);
    geom_scene_shade(&m, L, 2, NULL, &sp, sp.n, &c);
    assert_close(c.x, 0.4 + 0.6 * 0.8, 1e-15);
    assert_close(c.z, 0.6 * 0.8, 1e-15);
    /* n.l = -1: k_cool = (0,0,0.4) + 0.2 kd */
    L[0].position = geom_vec3_make(0, 0, -5);
    geom_scene_shade(&m, L, 1, NULL, &sp, sp.n, &c);
    assert_close(c.x, 0.16, 1e-15);
    assert_close(c.z, 0.56, 1e-15);
    assert_int_equal(geom_scene_material_needs(&m), GEOM_NEEDS_NORMAL);
}

static double ramp(uint32_t x, uint32_t y, uint32_t c)
{
    (void)y;
    (void)c;
    return (x + 0.5) / 32.0; /* height h(u) = u: slope 1 */
}

static double flat_normal(uint32_t x, uint32_t y, uint32_t c)
{
    (void)x;
    (void)y;
    static const double n[3] = {0.8, 0.5, 1.0}; /* (0.6, 0, 1) in [-1,1] */
    return n[c];
}

static void test_bump_and_normal_map(void **state)
{
    (void)state;
    geom_material m = geom_scene_material_default();
    geom_texture *h = make_tex(32, 32, 1, GEOM_WRAP_CLAMP, ramp);
    m.bump = h;
    m.bump_scale = 0.5;
    assert_int_equal(geom_scene_material_needs(&m), GEOM_NEEDS_NORMAL | GEOM_NEEDS_UV | GEOM_NEEDS_TANGENT);
    geom_shade_point sp = {0};
    sp.n = geom_vec3_make(0, 0, 1);
    sp.v = geom_vec3_make(0, 0, 1);
    sp.has_uv = 1;
    sp.uv[0] = sp.uv[1] = 0.5;
    sp.has_tangent = 1;
    sp.tangent = geom_vec3_make(1, 0, 0);
    /* the surface (u, v, 0.5 u) has normal (-0.5, 0, 1)/|.| */
    geom_vec3 n = geom_scene_shade_normal(&m, &sp);
    double l = sqrt(1.25);
    assert_close(n.x, -0.5 / l, 1e-12);
    assert_close(n.y, 0, 1e-12);
    assert_close(n.z, 1 / l, 1e-12);
    /* without tangents: unchanged */
    sp.has_tangent = 0;
    n = geom_scene_shade_normal(&m, &sp);
    assert_close(n.z, 1, 0);
    geom_scene_texture_destroy(h);
    m.bump = NULL;
    geom_texture *nmap = make_tex(4, 4, 3, GEOM_WRAP_REPEAT, flat_normal);
    m.normal_map = nmap;
    sp.has_tangent = 1;
    sp.tangent = geom_vec3_make(0, 1, 0); /* T = y, B = n x T = -x */
    n = geom_scene_shade_normal(&m, &sp);
    l = sqrt(1.36);
    assert_close(n.x, 0, 1e-12);
    assert_close(n.y, 0.6 / l, 1e-12);
    assert_close(n.z, 1 / l, 1e-12);
    geom_scene_texture_destroy(nmap);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_camera_ray_project),
        cmocka_unit_test(test_texture),
        cmocka_unit_test(test_shade_closed_forms),
        cmocka_unit_test(test_bump_and_normal_map),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
