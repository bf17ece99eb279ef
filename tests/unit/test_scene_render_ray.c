/*
 * geom_scene_render's ray path against closed forms for what it used to
 * drop: a textured mesh quad (VERTEX uv, CORNER uv, under a transform, one
 * polygon face; also read back from a ray-module scene, the scene JSON
 * path) matches the analytic perspective-correct mapping (and on
 * the raster path through geom_scene_render, which used to drop the UVs); the
 * shadow of a transmissive slab on a ground plane is transmit^2 of the
 * light (two surfaces crossed) exactly where the segment to the light
 * crosses the slab, and a scene seen only through a ground plane still
 * builds the unseen caster; a constant displacement map lifts a quad by
 * the map's height (depth AOV); a subdivision surface is tessellated to
 * the camera's pixel tolerance (finer near, coarser far).
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
#include "geom/subdiv.h"

/* Quad z = 0 over [-1, 1]^2 (one face of 4 vertices) with uv = ((x+1)/4 +
 * 1/4, (y+1)/4 + 1/4), as a VERTEX channel or a CORNER channel. */
static geom_mesh *quad(int corner)
{
    double p[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    uint32_t sizes[1] = {4}, idx[4] = {0, 1, 2, 3};
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, 4, p, 1, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    uint32_t id;
    if (!corner) {
        assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_VERTEX, 2, &id), GEOM_OK);
        double *d = geom_mesh_channel_data(m, id);
        const double *q = geom_mesh_cpositions(m);
        for (size_t i = 0; i < geom_mesh_n_vertices(m); i++) {
            d[2 * i] = (q[3 * i] + 1) / 4 + 0.25;
            d[2 * i + 1] = (q[3 * i + 1] + 1) / 4 + 0.25;
        }
        return m;
    }
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &id), GEOM_OK);
    size_t nh = geom_mesh_n_halfedges(m);
    assert_int_equal(geom_mesh_corner_pool_resize(m, id, nh), GEOM_OK);
    double *d = geom_mesh_channel_data(m, id);
    uint32_t *ci = geom_mesh_corner_indices(m, id);
    const double *q = geom_mesh_cpositions(m);
    for (uint32_t h = 0; h < nh; h++) {
        if (geom_mesh_he_face(m, h) == GEOM_INVALID_INDEX)
            continue;
        uint32_t v = geom_mesh_he_vertex(m, h); /* the corner at the vertex h points to */
        ci[h] = h;
        d[2 * h] = (q[3 * v] + 1) / 4 + 0.25;
        d[2 * h + 1] = (q[3 * v + 1] + 1) / 4 + 0.25;
    }
    return m;
}

static void check_quad(int corner, int transformed, int method, int via_ray_scene)
{
    geom_texture *tex = uv_texture();
    geom_mesh *q = quad(corner);
    geom_material mat;
    geom_light amb;
    geom_camera cam;
    textured_quad_view(tex, &mat, &amb, &cam);
    /* transformed: the quad built at z = 0 is moved up by 0.5 and scaled by
     * 2 in x; the analytic plane follows */
    geom_mat4 M = geom_mat4_mul(geom_mat4_translate(geom_vec3_make(0, 0, 0.5)),
                                geom_mat4_scale(geom_vec3_make(2, 1, 1)));
    double z0 = transformed ? 0.5 : 0, sx = transformed ? 2 : 1;
    geom_shape s;
    memset(&s, 0, sizeof s);
    s.kind = GEOM_SHAPE_MESH;
    s.mesh = q;
    s.transform = transformed ? &M : NULL;
    geom_scene_object o = {&s, 0};
    geom_ray_scene *rs = NULL;
    geom_scene_shapes *shapes = NULL;
    if (via_ray_scene) {
        /* the scene JSON path: a ray-module node read back as a shape */
        uint32_t id;
        rs = geom_ray_scene_create(NULL);
        assert_int_equal(geom_ray_scene_add_mesh(rs, q, &id), GEOM_OK);
        if (transformed)
            assert_int_equal(geom_ray_scene_set_transform(rs, id, M.m), GEOM_OK);
        assert_int_equal(geom_scene_shapes_from_ray(rs, &shapes, NULL), GEOM_OK);
        assert_int_equal(geom_scene_shapes_count(shapes), 1);
        o.shape = geom_scene_shapes_get(shapes, 0);
    }
    geom_image out = {0};
    geom_render_object_report orep;
    geom_render_options ro;
    memset(&ro, 0, sizeof ro);
    ro.method = (geom_render_method)method;
    assert_int_equal(geom_scene_render(&cam, &amb, 1, &mat, 1, &o, 1, &ro, &out, NULL, &orep, NULL),
                     GEOM_OK);
    assert_int_equal(orep.uvs, 1);
    assert_int_equal(orep.tessellated, method == GEOM_RENDER_RASTER);
    size_t checked = 0;
    double maxerr = 0;
    for (uint32_t j = 0; j < cam.height; j++)
        for (uint32_t i = 0; i < cam.width; i++) {
            geom_ray r;
            assert_int_equal(geom_scene_camera_ray(&cam, i + 0.5, j + 0.5, &r), GEOM_OK);
            const double *px = out.data + ((size_t)j * cam.width + i) * 3;
            if (!(r.dir.z < 0))
                continue;
            double t = (z0 - r.origin.z) / r.dir.z;
            double x = (r.origin.x + t * r.dir.x) / sx, y = r.origin.y + t * r.dir.y;
            if (fabs(x) > 0.99 || fabs(y) > 0.99)
                continue;
            double u = (x + 1) / 4 + 0.25, v = (y + 1) / 4 + 0.25;
            maxerr = fmax(maxerr, fmax(fabs(px[0] - u), fabs(px[1] - v)));
            checked++;
        }
    assert_true(checked > 3000);
    /* ray: exact (the texture is linear in uv); raster: MIP-mapped, as its own test */
    if (maxerr > (method == GEOM_RENDER_RAY ? 1e-9 : 2e-4))
        fail_msg("texture mapping off by %g (method %d, corner %d, transformed %d)", maxerr, method,
                 corner, transformed);
    geom_scene_image_free(&out, NULL);
    geom_scene_shapes_destroy(shapes);
    geom_ray_scene_destroy(rs);
    geom_mesh_destroy(q);
    geom_scene_texture_destroy(tex);
}

static void test_textured_mesh_quad(void **state)
{
    (void)state;
    for (int method = 0; method < 2; method++)
        for (int via = 0; via < 2; via++) {
            check_quad(0, 0, method, via);
            check_quad(1, 0, method, via);
            check_quad(1, 1, method, via);
            check_quad(0, 1, method, via);
        }
}

/* Number of the slab's faces the segment p -> L crosses (0 or 2), or -1
 * when it passes within eps of the slab's boundary. */
static int slab_crossings(const double p[3], const double L[3], const double mn[3],
                          const double mx[3], double eps)
{
    double t0 = 0, t1 = 1;
    int tight = 0;
    for (int k = 0; k < 3; k++) {
        double d = L[k] - p[k];
        if (d == 0) {
            if (p[k] < mn[k] - eps || p[k] > mx[k] + eps)
                return 0;
            if (p[k] < mn[k] + eps || p[k] > mx[k] - eps)
                tight = 1;
            continue;
        }
        double a = (mn[k] - p[k]) / d, b = (mx[k] - p[k]) / d;
        if (a > b) {
            double x = a;
            a = b;
            b = x;
        }
        t0 = fmax(t0, a);
        t1 = fmin(t1, b);
    }
    /* the segment's length inside the slab in parameter, against eps */
    double len = sqrt((L[0] - p[0]) * (L[0] - p[0]) + (L[1] - p[1]) * (L[1] - p[1]) +
                      (L[2] - p[2]) * (L[2] - p[2]));
    if (fabs(t1 - t0) * len < eps || tight)
        return -1;
    return t1 > t0 ? 2 : 0;
}

static void test_transmissive_shadow(void **state)
{
    (void)state;
    /* ground plane z = 0 (kd 1) under a point light; a slab out of view
     * with transmit 0.5 between the light and part of the ground; an
     * orthographic camera looking straight down at [-1, 1]^2 */
    geom_shape ground, slab;
    memset(&ground, 0, sizeof ground);
    ground.kind = GEOM_SHAPE_PLANE;
    ground.n[2] = 1;
    memset(&slab, 0, sizeof slab);
    slab.kind = GEOM_SHAPE_BOX;
    double mn[3] = {1.5, -3, 1}, mx[3] = {3, 0.2, 1.2};
    memcpy(slab.min, mn, sizeof mn);
    memcpy(slab.max, mx, sizeof mx);
    geom_material m[2];
    memset(m, 0, sizeof m);
    m[0].kd = geom_vec3_make(1, 1, 1);
    m[1].kd = geom_vec3_make(0.2, 0.2, 0.2);
    m[1].transmit = 0.5;
    m[1].ior = 1.5;
    geom_scene_object o[2] = {{&ground, 0}, {&slab, 1}};
    geom_light L;
    memset(&L, 0, sizeof L);
    L.kind = GEOM_LIGHT_POINT;
    L.position = geom_vec3_make(6, 0, 4);
    L.color = geom_vec3_make(1, 1, 1);
    geom_camera cam;
    memset(&cam, 0, sizeof cam);
    cam.projection = GEOM_PROJECTION_ORTHOGRAPHIC;
    cam.eye = geom_vec3_make(0, 0, 0.5);
    cam.center = geom_vec3_make(0, 0, 0);
    cam.up = geom_vec3_make(0, 1, 0);
    cam.ortho_height = 2;
    cam.width = cam.height = 64;
    geom_image img = {0};
    geom_render_object_report orep[2];
    geom_render_report rep;
    assert_int_equal(geom_scene_render(&cam, &L, 1, m, 2, o, 2, NULL, &img, &rep, orep, NULL), GEOM_OK);
    assert_true(!orep[1].visible && orep[1].needed); /* the ground can be shadowed by it */
    size_t lit = 0, half = 0;
    double Lp[3] = {6, 0, 4};
    for (uint32_t j = 0; j < 64; j++)
        for (uint32_t i = 0; i < 64; i++) {
            double p[3] = {-1 + (i + 0.5) / 32.0, 1 - (j + 0.5) / 32.0, 0};
            int k = slab_crossings(p, Lp, mn, mx, 1e-6);
            if (k < 0)
                continue;
            double dx = Lp[0] - p[0], dy = Lp[1] - p[1], dz = Lp[2] - p[2];
            double nl = dz / sqrt(dx * dx + dy * dy + dz * dz);
            double want = nl * (k == 2 ? 0.25 : 1.0);
            const double *px = img.data + ((size_t)j * 64 + i) * 3;
            assert_close(px[0], want, 1e-12);
            assert_close(px[2], want, 1e-12);
            if (k == 2)
                half++;
            else
                lit++;
        }
    assert_true(half > 300 && lit > 300);
    geom_scene_image_free(&img, NULL);
    /* an opaque slab: a full shadow */
    m[1].transmit = 0;
    assert_int_equal(geom_scene_render(&cam, &L, 1, m, 2, o, 2, NULL, &img, &rep, orep, NULL), GEOM_OK);
    double p[3] = {1 - 0.5 / 32, 0 - 0.5 / 32, 0};
    assert_int_equal(slab_crossings(p, Lp, mn, mx, 1e-6), 2);
    assert_close(img.data[((size_t)32 * 64 + 63) * 3], 0, 0);
    geom_scene_image_free(&img, NULL);
}

static void test_displacement_ray(void **state)
{
    (void)state;
    /* a constant height map of 0.25 (times scale 2): the quad rises to z = 0.5 */
    geom_image h = {0};
    assert_int_equal(geom_scene_image_init(&h, 2, 2, 1, NULL), GEOM_OK);
    for (int k = 0; k < 4; k++)
        h.data[k] = 0.25;
    geom_texture *ht;
    assert_int_equal(geom_scene_texture_create(&h, GEOM_WRAP_CLAMP, NULL, &ht), GEOM_OK);
    geom_scene_image_free(&h, NULL);
    geom_mesh *q = quad(0);
    geom_material mat = geom_scene_material_default();
    mat.displace = ht;
    mat.displace_scale = 2;
    geom_shape s;
    memset(&s, 0, sizeof s);
    s.kind = GEOM_SHAPE_MESH;
    s.mesh = q;
    geom_scene_object o = {&s, 0};
    geom_light amb = {0};
    amb.kind = GEOM_LIGHT_AMBIENT;
    amb.color = geom_vec3_make(1, 1, 1);
    geom_camera cam;
    memset(&cam, 0, sizeof cam);
    cam.projection = GEOM_PROJECTION_ORTHOGRAPHIC;
    cam.eye = geom_vec3_make(0, 0, 3);
    cam.center = geom_vec3_make(0, 0, 0);
    cam.up = geom_vec3_make(0, 1, 0);
    cam.ortho_height = 1.5;
    cam.width = cam.height = 16;
    geom_render_options ro;
    memset(&ro, 0, sizeof ro);
    ro.aov = GEOM_AOV_DEPTH;
    geom_image img = {0};
    geom_render_object_report orep;
    for (int method = 0; method < 2; method++) {
        ro.method = (geom_render_method)method;
        assert_int_equal(geom_scene_render(&cam, &amb, 1, &mat, 1, &o, 1, &ro, &img, NULL, &orep, NULL),
                         GEOM_OK);
        assert_int_equal(orep.displaced, 1);
        assert_int_equal(orep.tessellated, 1);
        for (size_t k = 0; k < 256; k++)
            assert_close(img.data[k], 2.5, 1e-9);
        geom_scene_image_free(&img, NULL);
    }
    geom_mesh_destroy(q);
    geom_scene_texture_destroy(ht);
}

static geom_mesh *cube(void)
{
    double p[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                    -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
    uint32_t sizes[6] = {4, 4, 4, 4, 4, 4};
    uint32_t idx[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 2, 3, 7, 6, 1, 2, 6, 5, 0, 4, 7, 3};
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, 8, p, 6, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    return m;
}

static void test_subdivision_pixel_error(void **state)
{
    (void)state;
    geom_mesh *c = cube();
    geom_shape s;
    memset(&s, 0, sizeof s);
    s.kind = GEOM_SHAPE_SUBDIV;
    s.mesh = c;
    s.scheme = GEOM_SUBDIV_CATMULL_CLARK;
    geom_scene_object o = {&s, 0};
    geom_material mat = geom_scene_material_default();
    geom_light L = {0};
    L.kind = GEOM_LIGHT_DIRECTIONAL;
    L.direction = geom_vec3_make(-1, -1, -1);
    L.color = geom_vec3_make(1, 1, 1);
    size_t tris[2];
    double tol[2];
    for (int far = 0; far < 2; far++) {
        geom_camera cam;
        memset(&cam, 0, sizeof cam);
        cam.eye = geom_vec3_make(0, -(far ? 60 : 5), 1);
        cam.center = geom_vec3_make(0, 0, 0);
        cam.up = geom_vec3_make(0, 0, 1);
        cam.fovy_degrees = 40;
        cam.width = 64;
        cam.height = 48;
        geom_image img = {0};
        geom_render_object_report orep;
        assert_int_equal(geom_scene_render(&cam, &L, 1, &mat, 1, &o, 1, NULL, &img, NULL, &orep, NULL),
                         GEOM_OK);
        geom_scene_image_free(&img, NULL);
        assert_int_equal(orep.tessellated, 1);
        assert_int_equal(orep.acceleration, 1);
        /* half a pixel at the nearest depth: 0.5 * 2 d tan(20 deg) / 48 */
        double d = far ? 59 : 4;
        double want = 0.5 * 2 * d * tan(20 * 3.14159265358979323846 / 180) / 48;
        assert_true(fabs(orep.tolerance - want) < 0.15 * want);
        assert_true(orep.tess.error.max_error <= orep.tolerance);
        tris[far] = orep.tess.triangles;
        tol[far] = orep.tolerance;
    }
    assert_true(tol[1] > 10 * tol[0]);
    assert_true(tris[1] < tris[0]);
    geom_mesh_destroy(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_textured_mesh_quad),
        cmocka_unit_test(test_transmissive_shadow),
        cmocka_unit_test(test_displacement_ray),
        cmocka_unit_test(test_subdivision_pixel_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
