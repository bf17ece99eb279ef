/* Helpers shared by the scene tests (test_scene_*.c). Header-only. */
#ifndef GEOM_TESTS_SCENE_TESTUTIL_H
#define GEOM_TESTS_SCENE_TESTUTIL_H

#include "unit/test_util.h"

#include "geom/scene.h"

/* Triangles of m's live faces (valence - 2 each). */
static inline size_t tri_count(const geom_mesh *m)
{
    size_t n = 0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); f++)
        if (!geom_mesh_face_is_deleted(m, f))
            n += geom_mesh_face_valence(m, f) - 2;
    return n;
}

/* The 64x64 uv texture's texel (x, y), channel c: its own uv centre (v up). */
static inline double uv_of(uint32_t x, uint32_t y, uint32_t c)
{
    return c == 0 ? (x + 0.5) / 64.0 : 1.0 - (y + 0.5) / 64.0;
}

/* A 64x64 3-channel clamped texture whose texels hold uv_of. */
static inline geom_texture *uv_texture(void)
{
    geom_image img = {0};
    assert_int_equal(geom_scene_image_init(&img, 64, 64, 3, NULL), GEOM_OK);
    for (uint32_t y = 0; y < 64; y++)
        for (uint32_t x = 0; x < 64; x++)
            for (uint32_t c = 0; c < 3; c++)
                img.data[(y * 64 + x) * 3 + c] = uv_of(x, y, c);
    geom_texture *tex;
    assert_int_equal(geom_scene_texture_create(&img, GEOM_WRAP_CLAMP, NULL, &tex), GEOM_OK);
    geom_scene_image_free(&img, NULL);
    return tex;
}

/* The textured-quad view: an ambient-only material showing tex (ka = 1), a
 * white ambient light, and a 160x120 perspective camera looking down at the
 * z = 0 plane at an angle. */
static inline void textured_quad_view(geom_texture *tex, geom_material *mat, geom_light *amb,
                                      geom_camera *cam)
{
    *mat = (geom_material){0};
    mat->ka = geom_vec3_make(1, 1, 1);
    mat->texture = tex;
    *amb = (geom_light){0};
    amb->kind = GEOM_LIGHT_AMBIENT;
    amb->color = geom_vec3_make(1, 1, 1);
    *cam = (geom_camera){0};
    cam->eye = geom_vec3_make(0.3, -2.2, 1.3);
    cam->center = geom_vec3_make(0.1, 0.2, 0);
    cam->up = geom_vec3_make(0, 0, 1);
    cam->fovy_degrees = 50;
    cam->width = 160;
    cam->height = 120;
}

#endif
