/* Camera: defaults, primary rays, view/projection matrices, projection of
 * points and the world size of a pixel. */
#include "geom/scene.h"

#include <math.h>

#include "core/internal.h"
#include "scene/scene_internal.h"

geom_camera geom_scene_camera_resolved(const geom_camera *cam)
{
    geom_camera c = *cam;
    if (c.up.x == 0 && c.up.y == 0 && c.up.z == 0)
        c.up = geom_vec3_make(0, 1, 0);
    if (c.fovy_degrees == 0)
        c.fovy_degrees = 45;
    if (c.ortho_height == 0)
        c.ortho_height = 2;
    if (c.width == 0)
        c.width = 320;
    if (c.height == 0)
        c.height = 240;
    if (c.samples == 0)
        c.samples = 1;
    if (c.max_samples == 0)
        c.max_samples = 64;
    if (c.tolerance == 0)
        c.tolerance = 1.0 / 512;
    if (c.seed == 0)
        c.seed = 0x9e3779b97f4a7c15ull;
    return c;
}

/* Orthonormal frame: f forward, s right, u up. */
static geom_status frame(const geom_camera *c, geom_vec3 *f, geom_vec3 *s, geom_vec3 *u)
{
    geom_status st = geom_vec3_normalize(geom_vec3_sub(c->center, c->eye), f);
    if (st != GEOM_OK)
        return st;
    st = geom_vec3_normalize(geom_vec3_cross(*f, c->up), s);
    if (st != GEOM_OK)
        return st;
    *u = geom_vec3_cross(*s, *f);
    if (c->projection == GEOM_PROJECTION_PERSPECTIVE) {
        if (!(c->fovy_degrees > 0 && c->fovy_degrees < 180))
            return GEOM_ERR_DOMAIN;
    } else if (!(c->ortho_height > 0) || !isfinite(c->ortho_height)) {
        return GEOM_ERR_DOMAIN;
    }
    return GEOM_OK;
}

geom_status geom__scene_cam_init(const geom_camera *cam, geom__scene_cam *k)
{
    k->c = geom_scene_camera_resolved(cam);
    geom_status st = frame(&k->c, &k->f, &k->s, &k->u);
    if (st != GEOM_OK)
        return st;
    double aspect = (double)k->c.width / (double)k->c.height;
    if (k->c.projection == GEOM_PROJECTION_PERSPECTIVE) {
        double t = tan(k->c.fovy_degrees * GEOM_PI / 360.0);
        k->kx = t * aspect;
        k->ky = t;
    } else {
        k->kx = 0.5 * k->c.ortho_height * aspect;
        k->ky = 0.5 * k->c.ortho_height;
    }
    return GEOM_OK;
}

void geom__scene_cam_ray(const geom__scene_cam *k, double x, double y, geom_ray *out)
{
    double nx = (2.0 * x / k->c.width - 1.0) * k->kx, ny = (1.0 - 2.0 * y / k->c.height) * k->ky;
    out->tmin = 0;
    out->tmax = INFINITY;
    geom_vec3 off = geom__v3add(geom__v3scale(k->s, nx), geom__v3scale(k->u, ny));
    if (k->c.projection == GEOM_PROJECTION_PERSPECTIVE) {
        out->origin = k->c.eye;
        if (!geom__v3unit(geom__v3add(k->f, off), &out->dir))
            out->dir = k->f;
        return;
    }
    out->origin = geom__v3add(k->c.eye, off);
    out->dir = k->f;
}

geom_status geom_scene_camera_ray(const geom_camera *cam, double x, double y, geom_ray *out)
{
    if (!cam || !out)
        return GEOM_ERR_INVALID_ARG;
    geom__scene_cam k;
    geom_status st = geom__scene_cam_init(cam, &k);
    if (st != GEOM_OK)
        return st;
    geom__scene_cam_ray(&k, x, y, out);
    return GEOM_OK;
}

geom_status geom_scene_camera_matrices(const geom_camera *cam, double near_z, double far_z,
                                 geom_mat4 *view, geom_mat4 *proj)
{
    if (!cam)
        return GEOM_ERR_INVALID_ARG;
    geom_camera c = geom_scene_camera_resolved(cam);
    geom_vec3 f, s, u;
    geom_status st = frame(&c, &f, &s, &u);
    if (st != GEOM_OK)
        return st;
    if (!(near_z > 0 && far_z > near_z))
        return GEOM_ERR_DOMAIN;
    if (view) {
        st = geom_mat4_lookat(c.eye, c.center, c.up, view);
        if (st != GEOM_OK)
            return st;
    }
    if (proj) {
        double aspect = (double)c.width / (double)c.height;
        if (c.projection == GEOM_PROJECTION_PERSPECTIVE)
            st = geom_mat4_perspective(c.fovy_degrees * GEOM_PI / 180.0, aspect, near_z, far_z,
                                       proj);
        else {
            double h = 0.5 * c.ortho_height;
            st = geom_mat4_ortho(-h * aspect, h * aspect, -h, h, near_z, far_z, proj);
        }
    }
    return st;
}

geom_status geom_scene_camera_project(const geom_camera *cam, geom_vec3 p, double out[3])
{
    if (!cam || !out)
        return GEOM_ERR_INVALID_ARG;
    geom_camera c = geom_scene_camera_resolved(cam);
    geom_vec3 f, s, u;
    geom_status st = frame(&c, &f, &s, &u);
    if (st != GEOM_OK)
        return st;
    geom_vec3 d = geom_vec3_sub(p, c.eye);
    double z = geom_vec3_dot(d, f), xs = geom_vec3_dot(d, s), ys = geom_vec3_dot(d, u);
    double aspect = (double)c.width / (double)c.height, nx, ny;
    if (c.projection == GEOM_PROJECTION_PERSPECTIVE) {
        if (!(z > 0))
            return GEOM_ERR_DOMAIN;
        double t = tan(c.fovy_degrees * GEOM_PI / 360.0);
        nx = xs / (z * t * aspect);
        ny = ys / (z * t);
    } else {
        double h = 0.5 * c.ortho_height;
        nx = xs / (h * aspect);
        ny = ys / h;
    }
    out[0] = 0.5 * (nx + 1.0) * c.width;
    out[1] = 0.5 * (1.0 - ny) * c.height;
    out[2] = z;
    return GEOM_OK;
}

double geom_scene_camera_pixel_size(const geom_camera *cam, double depth)
{
    geom_camera c = geom_scene_camera_resolved(cam);
    if (c.projection == GEOM_PROJECTION_ORTHOGRAPHIC)
        return c.ortho_height / c.height;
    return 2.0 * fabs(depth) * tan(c.fovy_degrees * GEOM_PI / 360.0) / c.height;
}

/* Widen [*lo, *hi] by the depths of b's corners along dir (scene_internal.h). */
void geom__scene_box_depth_range(geom_aabb b, geom_vec3 eye, geom_vec3 dir, double *lo,
                                 double *hi)
{
    for (int c = 0; c < 8; c++) {
        geom_vec3 p = geom_vec3_make(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y,
                                     c & 4 ? b.max.z : b.min.z);
        double d = geom_vec3_dot(geom_vec3_sub(p, eye), dir);
        *lo = fmin(*lo, d);
        *hi = fmax(*hi, d);
    }
}

/* Where the box lies against the frustum of vp: 0 outside, 1 inside, 2 cut. */
int geom__scene_box_frustum(geom_aabb b, geom_mat4 vp)
{
    int all_in = 1;
    int out_count[6] = {0};
    for (int c = 0; c < 8; c++) {
        geom_vec4 p = geom_vec4_make(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y,
                                     c & 4 ? b.max.z : b.min.z, 1);
        geom_vec4 q = geom_mat4_mul_vec4(vp, p);
        double a[3] = {q.x, q.y, q.z};
        for (int i = 0; i < 3; i++) {
            if (a[i] < -q.w) {
                out_count[2 * i]++;
                all_in = 0;
            }
            if (a[i] > q.w) {
                out_count[2 * i + 1]++;
                all_in = 0;
            }
        }
    }
    for (int i = 0; i < 6; i++)
        if (out_count[i] == 8)
            return 0;
    return all_in ? 1 : 2;
}


double geom_scene_pixel_tolerance(const geom_camera *cam_in, geom_aabb box, double pixel_error,
                                  int *visible)
{
    if (visible)
        *visible = 0;
    if (!cam_in || geom_aabb_is_empty(box) || !(pixel_error > 0))
        return 0;
    geom_camera cam = geom_scene_camera_resolved(cam_in);
    geom_vec3 f;
    if (geom_vec3_normalize(geom_vec3_sub(cam.center, cam.eye), &f) != GEOM_OK)
        return 0;
    double diag = geom_vec3_length(geom_vec3_sub(box.max, box.min));
    double dmin = INFINITY, dmax = -INFINITY;
    geom__scene_box_depth_range(box, cam.eye, f, &dmin, &dmax);
    int vis = 0;
    if (dmax > 0 || cam.projection == GEOM_PROJECTION_ORTHOGRAPHIC) {
        double near = cam.projection == GEOM_PROJECTION_ORTHOGRAPHIC ? 1 : fmax(dmax * 1e-6, 1e-300);
        double far = cam.projection == GEOM_PROJECTION_ORTHOGRAPHIC ? 2 : fmax(dmax, near) * 2;
        geom_mat4 view, proj;
        if (cam.projection == GEOM_PROJECTION_ORTHOGRAPHIC) {
            double h = 0.5 * cam.ortho_height, asp = (double)cam.width / cam.height;
            geom_mat4_lookat(cam.eye, cam.center, cam.up, &view);
            double lo = fmin(dmin, 0) - 1, hi = fmax(dmax, 0) + 1;
            geom_mat4_ortho(-h * asp, h * asp, -h, h, lo, hi, &proj);
            vis = geom__scene_box_frustum(box, geom_mat4_mul(proj, view)) != 0;
        } else if (geom_scene_camera_matrices(&cam, near, far, &view, &proj) == GEOM_OK) {
            vis = geom__scene_box_frustum(box, geom_mat4_mul(proj, view)) != 0;
        }
    }
    if (visible)
        *visible = vis;
    /* the nearest depth at which the object can be seen, not closer than
     * 1e-3 of its size (an eye inside the box) */
    double d = fmax(dmin, 1e-3 * diag);
    if (!vis) {
        /* unseen: by its distance from the eye */
        geom_vec3 q = geom_vec3_make(fmin(fmax(cam.eye.x, box.min.x), box.max.x),
                                     fmin(fmax(cam.eye.y, box.min.y), box.max.y),
                                     fmin(fmax(cam.eye.z, box.min.z), box.max.z));
        d = fmax(geom_vec3_length(geom_vec3_sub(q, cam.eye)), 1e-3 * diag);
    }
    double tol = pixel_error * geom_scene_camera_pixel_size(&cam, d);
    return vis ? tol : 8 * tol;
}
