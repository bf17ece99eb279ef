/*
 * scene ray tracing against closed forms: an orthographic Lambertian sphere
 * lit from the eye is kd n_z at every interior pixel; the shadow of a sphere
 * on a plane under a point light covers exactly the analytic region at pixel
 * centres; the Blinn-Phong highlight sits where the half vector meets the
 * normal; a glass slab shifts an edge by what Snell's law gives; total
 * internal reflection happens exactly beyond the critical angle. Only what
 * the scene needs: objects out of sight and out of every shadow are not
 * built, no refraction rays without transmissive materials, attributes only
 * for the materials that use them. Ray and raster agree within 1% on a
 * diffuse scene away from edges.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/scene.h"

#define PI 3.14159265358979323846

static geom_shape sphere_shape(double x, double y, double z, double r)
{
    geom_shape s;
    memset(&s, 0, sizeof s);
    s.kind = GEOM_SHAPE_SPHERE;
    s.p[0] = x;
    s.p[1] = y;
    s.p[2] = z;
    s.radius = r;
    return s;
}

static geom_shape plane_shape(double z)
{
    geom_shape s;
    memset(&s, 0, sizeof s);
    s.kind = GEOM_SHAPE_PLANE;
    s.p[2] = z;
    s.n[2] = 1;
    return s;
}

static geom_camera ortho_cam(uint32_t w, uint32_t h, double height)
{
    geom_camera c;
    memset(&c, 0, sizeof c);
    c.eye = geom_vec3_make(0, 0, 5);
    c.center = geom_vec3_make(0, 0, 0);
    c.projection = GEOM_PROJECTION_ORTHOGRAPHIC;
    c.ortho_height = height;
    c.width = w;
    c.height = h;
    return c;
}

static void test_lambert_sphere(void **state)
{
    (void)state;
    geom_shape s = sphere_shape(0, 0, 0, 1);
    geom_scene_object o = {&s, 0};
    geom_material m;
    memset(&m, 0, sizeof m);
    m.kd = geom_vec3_make(0.7, 0.5, 0.3);
    geom_light L;
    memset(&L, 0, sizeof L);
    L.kind = GEOM_LIGHT_DIRECTIONAL;
    L.direction = geom_vec3_make(0, 0, -1);
    L.color = geom_vec3_make(1, 1, 1);
    geom_camera cam = ortho_cam(101, 101, 2.2);
    geom_image img = {0};
    geom_render_report rep;
    geom_render_object_report orep;
    assert_int_equal(geom_scene_render(&cam, &L, 1, &m, 1, &o, 1, NULL, &img, &rep, &orep, NULL),
                     GEOM_OK);
    assert_int_equal(orep.tessellated, 0); /* analytic: never tessellated for ray */
    assert_int_equal(orep.acceleration, 0);
    assert_int_equal(rep.trace.refraction_rays, 0);
    assert_int_equal(rep.trace.reflection_rays, 0);
    size_t interior = 0;
    double maxerr = 0;
    for (uint32_t j = 0; j < 101; j++)
        for (uint32_t i = 0; i < 101; i++) {
            geom_ray r;
            geom_scene_camera_ray(&cam, i + 0.5, j + 0.5, &r);
            double rr = r.origin.x * r.origin.x + r.origin.y * r.origin.y;
            const double *px = img.data + 3 * ((size_t)j * 101 + i);
            if (rr > 1.0 - 0.05)
                continue; /* silhouette band */
            double nz = sqrt(1 - rr);
            maxerr = fmax(maxerr, fabs(px[0] - 0.7 * nz));
            maxerr = fmax(maxerr, fabs(px[2] - 0.3 * nz));
            interior++;
        }
    assert_true(interior > 6000);
    if (maxerr > 1e-9)
        fail_msg("Lambert sphere off by %g", maxerr);
    geom_scene_image_free(&img, NULL);
}

/* Does the segment q -> light meet the sphere (c, r)? */
static int occluded(geom_vec3 q, geom_vec3 light, geom_vec3 c, double r, double *margin)
{
    /* distance from the centre to the segment, minus r */
    geom_vec3 d = geom_vec3_sub(light, q), w = geom_vec3_sub(c, q);
    double t = geom_vec3_dot(w, d) / geom_vec3_dot(d, d);
    if (t < 0)
        t = 0;
    if (t > 1)
        t = 1;
    double dist = geom_vec3_length(geom_vec3_sub(w, geom_vec3_scale(d, t)));
    *margin = fabs(dist - r);
    return dist < r;
}

static void test_shadow_ellipse(void **state)
{
    (void)state;
    geom_vec3 c = geom_vec3_make(0.2, 0.1, 1), light = geom_vec3_make(1.5, -1, 4);
    double r = 0.6;
    geom_shape sh[2] = {plane_shape(0), sphere_shape(c.x, c.y, c.z, r)};
    geom_scene_object o[2] = {{&sh[0], 0}, {&sh[1], 0}};
    geom_material m = geom_scene_material_default();
    m.ka = geom_vec3_make(0.1, 0.1, 0.1);
    geom_light L[2];
    memset(L, 0, sizeof L);
    L[0].kind = GEOM_LIGHT_POINT;
    L[0].position = light;
    L[0].color = geom_vec3_make(1, 1, 1);
    L[1].kind = GEOM_LIGHT_AMBIENT;
    L[1].color = geom_vec3_make(1, 1, 1);
    geom_camera cam;
    memset(&cam, 0, sizeof cam);
    cam.eye = geom_vec3_make(-1, -4, 5);
    cam.center = geom_vec3_make(0, 0, 0);
    cam.up = geom_vec3_make(0, 0, 1);
    cam.fovy_degrees = 45;
    cam.width = 160;
    cam.height = 120;
    geom_image img = {0}, obj = {0};
    geom_render_options ro;
    memset(&ro, 0, sizeof ro);
    assert_int_equal(geom_scene_render(&cam, L, 2, &m, 1, o, 2, &ro, &img, NULL, NULL, NULL), GEOM_OK);
    ro.aov = GEOM_AOV_OBJECT;
    assert_int_equal(geom_scene_render(&cam, L, 2, &m, 1, o, 2, &ro, &obj, NULL, NULL, NULL), GEOM_OK);
    size_t shadow = 0, lit = 0;
    for (uint32_t j = 0; j < cam.height; j++)
        for (uint32_t i = 0; i < cam.width; i++) {
            size_t k = (size_t)j * cam.width + i;
            geom_ray ry;
            geom_scene_camera_ray(&cam, i + 0.5, j + 0.5, &ry);
            if (obj.data[k] != 0) {
                assert_true(obj.data[k] == 1 || ry.dir.z >= 0);
                continue;
            }
            double t = -ry.origin.z / ry.dir.z;
            geom_vec3 q = geom_vec3_add(ry.origin, geom_vec3_scale(ry.dir, t));
            double margin;
            int s = occluded(q, light, c, r, &margin);
            if (margin < 1e-9)
                continue;
            double v = img.data[3 * k];
            if (s) {
                if (fabs(v - 0.1) > 1e-12)
                    fail_msg("pixel %u %u should be in shadow: %g", i, j, v);
                shadow++;
            } else {
                if (!(v > 0.1 + 1e-6))
                    fail_msg("pixel %u %u should be lit: %g", i, j, v);
                lit++;
            }
        }
    assert_true(shadow > 500);
    assert_true(lit > 5000);
    geom_scene_image_free(&img, NULL);
    geom_scene_image_free(&obj, NULL);
}

static void test_blinn_highlight(void **state)
{
    (void)state;
    geom_shape s = sphere_shape(0, 0, 0, 1);
    geom_scene_object o = {&s, 0};
    geom_material m;
    memset(&m, 0, sizeof m);
    m.ks = geom_vec3_make(1, 1, 1);
    m.ns = 200;
    geom_light L;
    memset(&L, 0, sizeof L);
    L.kind = GEOM_LIGHT_DIRECTIONAL;
    geom_vec3 l = geom_vec3_make(0.5, 0.4, 0.7);
    geom_vec3_normalize(l, &l);
    L.direction = geom_vec3_neg(l);
    L.color = geom_vec3_make(1, 1, 1);
    geom_camera cam = ortho_cam(201, 201, 2.2);
    geom_image img = {0};
    assert_int_equal(geom_scene_render(&cam, &L, 1, &m, 1, &o, 1, NULL, &img, NULL, NULL, NULL), GEOM_OK);
    size_t best = 0;
    for (size_t k = 1; k < (size_t)201 * 201; k++)
        if (img.data[3 * k] > img.data[3 * best])
            best = k;
    /* n = h = normalize(l + v), v = +z; the point c + r n projects to (x, y) */
    geom_vec3 h;
    geom_vec3_normalize(geom_vec3_add(l, geom_vec3_make(0, 0, 1)), &h);
    double q[3];
    assert_int_equal(geom_scene_camera_project(&cam, h, q), GEOM_OK);
    double bi = (double)(best % 201) + 0.5, bj = (double)(best / 201) + 0.5;
    if (fabs(bi - q[0]) > 1 || fabs(bj - q[1]) > 1)
        fail_msg("highlight at %g %g, expected %g %g", bi, bj, q[0], q[1]);
    assert_true(img.data[3 * best] > 0.98); /* (n.h)^200 within a pixel of the peak */
    geom_scene_image_free(&img, NULL);
}

static void test_glass_slab_shift(void **state)
{
    (void)state;
    const double d = 0.5, ior = 1.5, th = 35 * PI / 180;
    geom_shape slab;
    memset(&slab, 0, sizeof slab);
    slab.kind = GEOM_SHAPE_BOX;
    slab.min[0] = -50; slab.min[1] = -50; slab.min[2] = 0;
    slab.max[0] = 50; slab.max[1] = 50; slab.max[2] = d;
    double white[12] = {-50, -50, -1, 0, -50, -1, 0, 50, -1, -50, 50, -1};
    double black[12] = {0, -50, -1, 50, -50, -1, 50, 50, -1, 0, 50, -1};
    geom_shape gw, gb;
    memset(&gw, 0, sizeof gw);
    gw.kind = GEOM_SHAPE_POLYGON;
    gw.vertices = white;
    gw.n_vertices = 4;
    gb = gw;
    gb.vertices = black;
    geom_material mats[3];
    memset(mats, 0, sizeof mats);
    mats[0].transmit = 1;
    mats[0].ior = ior;
    mats[1].ka = geom_vec3_make(1, 1, 1);
    mats[2].ka = geom_vec3_make(0, 0, 0);
    geom_light amb;
    memset(&amb, 0, sizeof amb);
    amb.kind = GEOM_LIGHT_AMBIENT;
    amb.color = geom_vec3_make(1, 1, 1);
    geom_camera cam;
    memset(&cam, 0, sizeof cam);
    cam.projection = GEOM_PROJECTION_ORTHOGRAPHIC;
    cam.eye = geom_vec3_make(-50 * sin(th), 0, 50 * cos(th));
    cam.center = geom_vec3_make(0, 0, 0);
    cam.ortho_height = 2;
    cam.width = 200;
    cam.height = 20;
    geom_render_options ro;
    memset(&ro, 0, sizeof ro);
    ro.max_depth = 4;
    for (int with_slab = 0; with_slab < 2; with_slab++) {
        geom_scene_object o[3] = {{&gw, 1}, {&gb, 2}, {&slab, 0}};
        geom_image img = {0};
        geom_render_report rep;
        assert_int_equal(geom_scene_render(&cam, &amb, 1, mats, 3, o, with_slab ? 3 : 2, &ro, &img,
                                           &rep, NULL, NULL),
                         GEOM_OK);
        assert_true(with_slab ? rep.trace.refraction_rays > 0 : rep.trace.refraction_rays == 0);
        /* the ground x each pixel centre sees: straight, or shifted by
         * d (tan theta_t - tan theta) */
        double tt = asin(sin(th) / ior);
        size_t checked = 0;
        for (uint32_t i = 0; i < cam.width; i++) {
            geom_ray r;
            geom_scene_camera_ray(&cam, i + 0.5, 10.5, &r);
            double t = (-1 - r.origin.z) / r.dir.z;
            double x = r.origin.x + t * r.dir.x;
            if (with_slab)
                x += d * (tan(tt) - tan(th));
            if (fabs(x) < 1e-9)
                continue;
            double v = img.data[3 * ((size_t)10 * cam.width + i)];
            if (!(fabs(v - (x < 0 ? 1.0 : 0.0)) < 1e-12))
                fail_msg("slab %d pixel %u: x %g value %g", with_slab, i, x, v);
            checked++;
        }
        assert_true(checked > 190);
        geom_scene_image_free(&img, NULL);
    }
}

static void test_total_internal_reflection(void **state)
{
    (void)state;
    /* camera inside a glass block looking up at the top face: TIR exactly
     * when the angle of incidence exceeds asin(1/1.5) = 41.81 degrees */
    geom_shape block;
    memset(&block, 0, sizeof block);
    block.kind = GEOM_SHAPE_BOX;
    block.min[0] = -100; block.min[1] = -100; block.min[2] = -100;
    block.max[0] = 100; block.max[1] = 100; block.max[2] = 1;
    geom_material m;
    memset(&m, 0, sizeof m);
    m.transmit = 1;
    m.ior = 1.5;
    geom_scene_object o = {&block, 0};
    geom_render_options ro;
    memset(&ro, 0, sizeof ro);
    ro.max_depth = 1;
    double crit = asin(1 / 1.5) * 180 / PI;
    double angles[4] = {crit - 1, crit - 0.01, crit + 0.01, crit + 1};
    for (int a = 0; a < 4; a++) {
        double th = angles[a] * PI / 180;
        geom_camera cam;
        memset(&cam, 0, sizeof cam);
        cam.projection = GEOM_PROJECTION_ORTHOGRAPHIC;
        cam.eye = geom_vec3_make(0, 0, 0);
        cam.center = geom_vec3_make(sin(th), 0, cos(th));
        cam.up = geom_vec3_make(0, 1, 0);
        cam.ortho_height = 0.5;
        cam.width = cam.height = 8;
        geom_image img = {0};
        geom_render_report rep;
        assert_int_equal(geom_scene_render(&cam, NULL, 0, &m, 1, &o, 1, &ro, &img, &rep, NULL, NULL),
                         GEOM_OK);
        if (angles[a] > crit) {
            /* the reflected ray (depth 1) meets the bottom face at the same
             * angle: a second TIR there, whose own reflection is cut */
            assert_int_equal(rep.trace.total_internal_reflections, 128);
            assert_int_equal(rep.trace.refraction_rays, 0);
        } else {
            assert_int_equal(rep.trace.total_internal_reflections, 0);
            assert_int_equal(rep.trace.refraction_rays, 64);
        }
        geom_scene_image_free(&img, NULL);
    }
}

static geom_mesh *tri_mesh(double z)
{
    double p[9] = {-1, -1, z, 1, -1, z, 0, 1, z};
    uint32_t sz = 3, idx[3] = {0, 1, 2};
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, 3, p, 1, &sz, idx, NULL, NULL, NULL), GEOM_OK);
    return m;
}

static void test_only_what_is_needed(void **state)
{
    (void)state;
    /* a sphere in view, a mesh behind the camera, a mesh off to the side
     * but between the sphere and the light (a shadow caster) */
    geom_mesh *behind = tri_mesh(20), *caster = tri_mesh(0);
    geom_shape s = sphere_shape(0, 0, 0, 1);
    geom_shape mb, mc;
    memset(&mb, 0, sizeof mb);
    mb.kind = GEOM_SHAPE_MESH;
    mb.mesh = behind;
    mc = mb;
    mc.mesh = caster;
    geom_mat4 up = geom_mat4_translate(geom_vec3_make(0, 6, 3));
    mc.transform = &up;
    geom_scene_object o[3] = {{&s, 0}, {&mb, 0}, {&mc, 0}};
    geom_material m[2] = {geom_scene_material_default(), geom_scene_material_default()};
    m[1].reflect = 0.5;
    geom_light L;
    memset(&L, 0, sizeof L);
    L.kind = GEOM_LIGHT_POINT;
    L.position = geom_vec3_make(0, 12, 6);
    L.color = geom_vec3_make(1, 1, 1);
    geom_camera cam;
    memset(&cam, 0, sizeof cam);
    cam.eye = geom_vec3_make(0, 0, 10);
    cam.center = geom_vec3_make(0, 0, 0);
    cam.fovy_degrees = 20;
    cam.width = cam.height = 32;
    geom_render_object_report orep[3];
    geom_render_report rep;
    geom_image img = {0};
    for (int method = 0; method < 2; method++) {
        geom_render_options ro;
        memset(&ro, 0, sizeof ro);
        ro.method = (geom_render_method)method;
        assert_int_equal(geom_scene_render(&cam, &L, 1, m, 2, o, 3, &ro, &img, &rep, orep, NULL),
                         GEOM_OK);
        geom_scene_image_free(&img, NULL);
        assert_true(orep[0].visible && orep[0].needed);
        assert_true(!orep[1].visible && !orep[1].needed);
        assert_true(!orep[2].visible && orep[2].needed);
        assert_int_equal(rep.objects_needed, 2);
        if (method == GEOM_RENDER_RAY) {
            assert_int_equal(rep.ray_build.meshes, 1); /* only the caster's BVH */
            assert_int_equal(orep[0].tessellated, 0);
            assert_int_equal(orep[1].acceleration, 0);
            assert_int_equal(orep[2].acceleration, 1);
            assert_int_equal(rep.trace.reflection_rays, 0);
            assert_int_equal(rep.trace.refraction_rays, 0);
        } else {
            assert_int_equal(orep[0].tessellated, 1);
            assert_int_equal(orep[1].tessellated, 0);
            assert_int_equal(orep[0].uvs, 0);
            assert_int_equal(orep[0].tangents, 0);
            assert_true(orep[0].tess.error.max_error <= orep[0].tolerance);
        }
    }
    /* a reflective sphere can see everything: all built */
    o[0].material = 1;
    assert_int_equal(geom_scene_render(&cam, &L, 1, m, 2, o, 3, NULL, &img, &rep, orep, NULL), GEOM_OK);
    geom_scene_image_free(&img, NULL);
    assert_int_equal(rep.objects_needed, 3);
    assert_true(rep.trace.reflection_rays > 0);
    assert_int_equal(rep.ray_build.meshes, 2);
    geom_mesh_destroy(behind);
    geom_mesh_destroy(caster);
}

static void test_ray_vs_raster(void **state)
{
    (void)state;
    geom_shape sh[3] = {plane_shape(0), sphere_shape(0, 0, 1, 1), sphere_shape(1.8, 0.8, 0.5, 0.5)};
    geom_scene_object o[3] = {{&sh[0], 0}, {&sh[1], 1}, {&sh[2], 1}};
    geom_material m[2] = {geom_scene_material_default(), geom_scene_material_default()};
    m[1].kd = geom_vec3_make(0.8, 0.4, 0.2);
    geom_light L[2];
    memset(L, 0, sizeof L);
    L[0].kind = GEOM_LIGHT_DIRECTIONAL;
    L[0].direction = geom_vec3_make(-0.3, -0.5, -1);
    geom_vec3_normalize(L[0].direction, &L[0].direction);
    L[0].color = geom_vec3_make(1, 1, 1);
    L[1].kind = GEOM_LIGHT_AMBIENT;
    L[1].color = geom_vec3_make(0.5, 0.5, 0.5);
    geom_camera cam;
    memset(&cam, 0, sizeof cam);
    cam.eye = geom_vec3_make(2, -6, 4);
    cam.center = geom_vec3_make(0.3, 0, 0.6);
    cam.up = geom_vec3_make(0, 0, 1);
    cam.fovy_degrees = 40;
    cam.width = 160;
    cam.height = 120;
    geom_image a = {0}, b = {0}, ida = {0};
    geom_render_options ro;
    memset(&ro, 0, sizeof ro);
    assert_int_equal(geom_scene_render(&cam, L, 2, m, 2, o, 3, &ro, &a, NULL, NULL, NULL), GEOM_OK);
    ro.aov = GEOM_AOV_OBJECT;
    assert_int_equal(geom_scene_render(&cam, L, 2, m, 2, o, 3, &ro, &ida, NULL, NULL, NULL), GEOM_OK);
    ro.aov = GEOM_AOV_COLOR;
    ro.method = GEOM_RENDER_RASTER;
    ro.shadow_map_size = 2048;
    geom_render_report rep;
    assert_int_equal(geom_scene_render(&cam, L, 2, m, 2, o, 3, &ro, &b, &rep, NULL, NULL), GEOM_OK);
    double diff = 0, sum = 0;
    size_t n = 0;
    int W = (int)cam.width, H = (int)cam.height;
    for (int j = 2; j < H - 2; j++)
        for (int i = 2; i < W - 2; i++) {
            /* away from edges: same object and no jump of the ray image in a
             * 5x5 neighbourhood (silhouettes, shadow boundaries) */
            int edge = 0;
            double c0 = a.data[3 * ((size_t)j * W + i)];
            for (int dj = -2; dj <= 2 && !edge; dj++)
                for (int di = -2; di <= 2; di++) {
                    size_t q = (size_t)(j + dj) * W + (size_t)(i + di);
                    if (ida.data[q] != ida.data[(size_t)j * W + i] || fabs(a.data[3 * q] - c0) > 0.1) {
                        edge = 1;
                        break;
                    }
                }
            if (edge || ida.data[(size_t)j * W + i] < 0)
                continue;
            for (int c = 0; c < 3; c++) {
                diff += fabs(a.data[3 * ((size_t)j * W + i) + c] - b.data[3 * ((size_t)j * W + i) + c]);
                sum += a.data[3 * ((size_t)j * W + i) + c];
            }
            n++;
        }
    assert_true(n > 8000);
    double rel = diff / sum;
    if (rel > 0.01)
        fail_msg("ray and raster differ by %.3f%% (mean abs / mean)", 100 * rel);
    geom_scene_image_free(&a, NULL);
    geom_scene_image_free(&b, NULL);
    geom_scene_image_free(&ida, NULL);
}

static void test_sampling(void **state)
{
    (void)state;
    geom_shape s = sphere_shape(0, 0, 0, 1);
    geom_scene_object o = {&s, 0};
    geom_material m = geom_scene_material_default();
    geom_light L;
    memset(&L, 0, sizeof L);
    L.kind = GEOM_LIGHT_DIRECTIONAL;
    L.direction = geom_vec3_make(0, 0, -1);
    L.color = geom_vec3_make(1, 1, 1);
    geom_camera cam = ortho_cam(40, 40, 2.5);
    geom_render_report r1, r2, r3;
    geom_image img = {0};
    assert_int_equal(geom_scene_render(&cam, &L, 1, &m, 1, &o, 1, NULL, &img, &r1, NULL, NULL), GEOM_OK);
    geom_scene_image_free(&img, NULL);
    assert_int_equal(r1.trace.primary_rays, 1600);
    assert_int_equal(r1.trace.image_error.method, GEOM_ERROR_NONE);
    cam.samples = 9;
    cam.sampling = GEOM_SAMPLING_JITTERED;
    assert_int_equal(geom_scene_render(&cam, &L, 1, &m, 1, &o, 1, NULL, &img, &r2, NULL, NULL), GEOM_OK);
    geom_scene_image_free(&img, NULL);
    assert_int_equal(r2.trace.primary_rays, 9 * 1600);
    assert_int_equal(r2.trace.image_error.method, GEOM_ERROR_ESTIMATE);
    assert_true(r2.trace.image_error.max_error > 0);
    cam.sampling = GEOM_SAMPLING_ADAPTIVE;
    cam.samples = 4;
    cam.max_samples = 64;
    cam.tolerance = 0.01;
    assert_int_equal(geom_scene_render(&cam, &L, 1, &m, 1, &o, 1, NULL, &img, &r3, NULL, NULL), GEOM_OK);
    geom_scene_image_free(&img, NULL);
    /* flat pixels stop at 4, silhouette pixels go on */
    assert_true(r3.trace.primary_rays < 16 * 1600);
    assert_true(r3.trace.max_samples_per_pixel > 4);
    assert_true(r3.trace.image_error.max_error < r2.trace.image_error.max_error ||
                r3.trace.max_samples_per_pixel == 64);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lambert_sphere),
        cmocka_unit_test(test_shadow_ellipse),
        cmocka_unit_test(test_blinn_highlight),
        cmocka_unit_test(test_glass_slab_shift),
        cmocka_unit_test(test_total_internal_reflection),
        cmocka_unit_test(test_only_what_is_needed),
        cmocka_unit_test(test_ray_vs_raster),
        cmocka_unit_test(test_sampling),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
