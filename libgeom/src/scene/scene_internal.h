/* Private helpers shared by the scene module's sources. */
#ifndef GEOM_SRC_SCENE_INTERNAL_H
#define GEOM_SRC_SCENE_INTERNAL_H

#include "geom/scene.h"

#include <math.h>

/* Inline vector helpers for the per-ray paths (core's are out of line). */
static inline geom_vec3 geom__v3(double x, double y, double z)
{
    geom_vec3 r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}
static inline geom_vec3 geom__v3add(geom_vec3 a, geom_vec3 b) { return geom__v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline geom_vec3 geom__v3sub(geom_vec3 a, geom_vec3 b) { return geom__v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline geom_vec3 geom__v3scale(geom_vec3 a, double s) { return geom__v3(a.x * s, a.y * s, a.z * s); }
static inline geom_vec3 geom__v3neg(geom_vec3 a) { return geom__v3(-a.x, -a.y, -a.z); }
static inline geom_vec3 geom__v3mul(geom_vec3 a, geom_vec3 b) { return geom__v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline double geom__v3dot(geom_vec3 a, geom_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline geom_vec3 geom__v3cross(geom_vec3 a, geom_vec3 b)
{
    return geom__v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
/* a / |a| into *u (1), or 0 for a zero or non-finite a (*u unchanged).
 * Squared lengths in (1e-280, 1e280) take the direct path; the rest go
 * through core's scaled normalisation. */
static inline int geom__v3unit(geom_vec3 a, geom_vec3 *u)
{
    double l2 = a.x * a.x + a.y * a.y + a.z * a.z;
    if (l2 > 1e-280 && l2 < 1e280) {
        double s = 1.0 / sqrt(l2);
        *u = geom__v3(a.x * s, a.y * s, a.z * s);
        return 1;
    }
    geom_vec3 v;
    if (geom_vec3_normalize(a, &v) != GEOM_OK)
        return 0;
    *u = v;
    return 1;
}

/* A camera with its frame computed once: primary rays without per-ray
 * normalisation of the frame. */
typedef struct geom__scene_cam {
    geom_camera c;       /* resolved */
    geom_vec3 f, s, u;   /* forward, right, up (orthonormal) */
    double kx, ky;       /* perspective: tan(fovy/2)*aspect, tan(fovy/2); ortho: half sizes */
} geom__scene_cam;

/* Statuses as geom_scene_camera_ray. */
geom_status geom__scene_cam_init(const geom_camera *cam, geom__scene_cam *out);
/* The primary ray through pixel point (x, y), as geom_scene_camera_ray. */
void geom__scene_cam_ray(const geom__scene_cam *k, double x, double y, geom_ray *out);

/* World-space bounding box of a draw (its mesh's box, transformed). */
geom_aabb geom__scene_draw_bbox(const geom_scene_draw *d);

/* Widen [*lo, *hi] by the depths of box b's 8 corners along dir from eye
 * (dot(corner - eye, dir), taken with fmin/fmax): the depth range of a box
 * seen from a camera. */
void geom__scene_box_depth_range(geom_aabb b, geom_vec3 eye, geom_vec3 dir, double *lo,
                                 double *hi);

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
 * in [r->tmin, r->tmax], 0 on a miss. visibility: the fraction of light that
 * passes along r over [tmin, tmax] (1: nothing hit, 0: an opaque hit; see
 * geom_scene_trace for transmissive surfaces). Formerly: 1 if anything is hit in
 * [tmin, tmax]. spawn: a new ray's origin leaving the surface of h toward
 * dir (offset by the hit's error bound). */
typedef struct geom__tracer {
    void *user;
    int (*closest)(void *user, const geom_ray *r, geom__scene_hit *h);
    double (*visibility)(void *user, const geom_ray *r);
    geom_vec3 (*spawn)(void *user, const geom__scene_hit *h, geom_vec3 dir);
} geom__tracer;

geom_status geom__scene_trace(const geom__tracer *tr, const geom_camera *cam,
                              const geom_light *lights, size_t n_lights,
                              const geom_material *materials, size_t n_materials,
                              const geom_trace_options *opt, geom_image *out,
                              geom_trace_report *report);

/* geom_scene_tessellate_estimate; cheap: for marching-cubes shapes, no
 * pass of geom_scene_tessellate's tried, the last one assumed and its count
 * scaled from a coarse grid's (an upper bound costing at most about 1/8 of
 * the tessellation; see geom_export_options.max_triangles). */
geom_status geom__scene_tessellate_estimate(const geom_shape *s, const geom_tess_request *rq,
                                            int cheap, double *triangles);

#endif
