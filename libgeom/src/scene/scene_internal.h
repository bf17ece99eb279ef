/* Private helpers shared by the scene module's sources. */
#ifndef GEOM_SRC_SCENE_INTERNAL_H
#define GEOM_SRC_SCENE_INTERNAL_H

#include "geom/scene.h"

/* World-space bounding box of a draw (its mesh's box, transformed). */
geom_aabb geom__scene_draw_bbox(const geom_scene_draw *d);

/* Where box b lies against the frustum of the clip matrix vp: 0 outside,
 * 1 inside, 2 cut. */
int geom__scene_box_frustum(geom_aabb b, geom_mat4 vp);

/* A surface hit as the Whitted tracer needs it. */
typedef struct geom__scene_hit {
    double t;
    geom_vec3 p;   /* world point */
    geom_vec3 ng;  /* unit geometric normal, stored orientation (outward for solids) */
    geom_vec3 n;   /* unit shading normal, same side as ng */
    double uv[2];
    int has_uv;
    geom_vec3 tangent;
    double tangent_sign;
    int has_tangent;
    uint32_t object;   /* index of the top-level object */
    uint32_t material; /* index into the materials */
    geom_ray_hit raw;  /* the ray module's hit (error bounds for spawning) */
} geom__scene_hit;

/* Where the tracer gets its intersections from. closest: 1 and *h on a hit
 * in [r->tmin, r->tmax], 0 on a miss. occluded: 1 if anything is hit in
 * [tmin, tmax]. spawn: a new ray's origin leaving the surface of h toward
 * dir (offset by the hit's error bound). */
typedef struct geom__tracer {
    void *user;
    int (*closest)(void *user, const geom_ray *r, geom__scene_hit *h);
    int (*occluded)(void *user, const geom_ray *r);
    geom_vec3 (*spawn)(void *user, const geom__scene_hit *h, geom_vec3 dir);
} geom__tracer;

geom_status geom__scene_trace(const geom__tracer *tr, const geom_camera *cam,
                              const geom_light *lights, size_t n_lights,
                              const geom_material *materials, size_t n_materials,
                              const geom_trace_options *opt, geom_image *out,
                              geom_trace_report *report);

#endif
