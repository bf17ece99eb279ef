/* Camera: defaults, primary rays, view/projection matrices, projection of
 * points and the world size of a pixel. */
#include "geom/scene.h"

#include <math.h>

#include "core/internal.h"

geom_camera geom_camera_resolved(const geom_camera *cam)
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

geom_status geom_camera_ray(const geom_camera *cam, double x, double y, geom_ray *out)
{
    if (!cam || !out)
        return GEOM_ERR_INVALID_ARG;
    geom_camera c = geom_camera_resolved(cam);
    geom_vec3 f, s, u;
    geom_status st = frame(&c, &f, &s, &u);
    if (st != GEOM_OK)
        return st;
    double aspect = (double)c.width / (double)c.height;
    double nx = 2.0 * x / c.width - 1.0, ny = 1.0 - 2.0 * y / c.height;
    out->tmin = 0;
    out->tmax = INFINITY;
    if (c.projection == GEOM_PROJECTION_PERSPECTIVE) {
        double t = tan(c.fovy_degrees * GEOM_PI / 360.0);
        geom_vec3 d = geom_vec3_add(f, geom_vec3_add(geom_vec3_scale(s, nx * t * aspect),
                                                     geom_vec3_scale(u, ny * t)));
        out->origin = c.eye;
        return geom_vec3_normalize(d, &out->dir);
    }
    double h = 0.5 * c.ortho_height;
    out->origin = geom_vec3_add(c.eye, geom_vec3_add(geom_vec3_scale(s, nx * h * aspect),
                                                     geom_vec3_scale(u, ny * h)));
    out->dir = f;
    return GEOM_OK;
}

geom_status geom_camera_matrices(const geom_camera *cam, double near_z, double far_z,
                                 geom_mat4 *view, geom_mat4 *proj)
{
    if (!cam)
        return GEOM_ERR_INVALID_ARG;
    geom_camera c = geom_camera_resolved(cam);
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

geom_status geom_camera_project(const geom_camera *cam, geom_vec3 p, double out[3])
{
    if (!cam || !out)
        return GEOM_ERR_INVALID_ARG;
    geom_camera c = geom_camera_resolved(cam);
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

double geom_camera_pixel_size(const geom_camera *cam, double depth)
{
    geom_camera c = geom_camera_resolved(cam);
    if (c.projection == GEOM_PROJECTION_ORTHOGRAPHIC)
        return c.ortho_height / c.height;
    return 2.0 * fabs(depth) * tan(c.fovy_degrees * GEOM_PI / 360.0) / c.height;
}
