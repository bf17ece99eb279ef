/* Affine transforms, camera and projection matrices (OpenGL conventions). */
#include "core/internal.h"

#define M4(a, r, c) ((a).m[4 * (c) + (r)])

geom_mat4 geom_mat4_translate(geom_vec3 t)
{
    geom_mat4 r = geom_mat4_identity();
    M4(r, 0, 3) = t.x;
    M4(r, 1, 3) = t.y;
    M4(r, 2, 3) = t.z;
    return r;
}

geom_mat4 geom_mat4_scale(geom_vec3 s)
{
    geom_mat4 r = geom_mat4_identity();
    M4(r, 0, 0) = s.x;
    M4(r, 1, 1) = s.y;
    M4(r, 2, 2) = s.z;
    return r;
}

geom_status geom_mat4_rotate(geom_vec3 axis, double radians, geom_mat4 *out)
{
    geom_vec3 u;
    geom_status s = geom_vec3_normalize(axis, &u);
    if (s == GEOM_OK && !isfinite(radians))
        s = GEOM_ERR_INVALID_ARG;
    if (s != GEOM_OK) {
        if (out)
            *out = geom_mat4_identity();
        return s;
    }
    double c = cos(radians), sn = sin(radians), t = 1.0 - c;
    geom_mat4 r = geom_mat4_identity();
    /* Rodrigues' rotation formula: R = c I + s [u]x + (1 - c) u u^T. */
    M4(r, 0, 0) = c + t * u.x * u.x;
    M4(r, 0, 1) = t * u.x * u.y - sn * u.z;
    M4(r, 0, 2) = t * u.x * u.z + sn * u.y;
    M4(r, 1, 0) = t * u.y * u.x + sn * u.z;
    M4(r, 1, 1) = c + t * u.y * u.y;
    M4(r, 1, 2) = t * u.y * u.z - sn * u.x;
    M4(r, 2, 0) = t * u.z * u.x - sn * u.y;
    M4(r, 2, 1) = t * u.z * u.y + sn * u.x;
    M4(r, 2, 2) = c + t * u.z * u.z;
    if (out)
        *out = r;
    return GEOM_OK;
}

geom_status geom_mat4_transform_point(geom_mat4 a, geom_vec3 p, geom_vec3 *out)
{
    geom_vec4 h = geom_mat4_mul_vec4(a, geom_vec4_make(p.x, p.y, p.z, 1.0));
    return geom_vec4_homogeneous_divide(h, out);
}

geom_vec3 geom_mat4_transform_dir(geom_mat4 a, geom_vec3 v)
{
    return geom_mat3_mul_vec3(geom_mat4_upper3(a), v);
}

geom_status geom_mat4_lookat(geom_vec3 eye, geom_vec3 center, geom_vec3 up, geom_mat4 *out)
{
    geom_vec3 f, s, u;
    geom_status st = geom_vec3_normalize(geom_vec3_sub(center, eye), &f);
    if (st == GEOM_OK)
        st = geom_vec3_normalize(geom_vec3_cross(f, up), &s);
    if (st != GEOM_OK) {
        if (out)
            *out = geom_mat4_identity();
        return st;
    }
    u = geom_vec3_cross(s, f);
    geom_mat4 r = geom_mat4_identity();
    M4(r, 0, 0) = s.x;
    M4(r, 0, 1) = s.y;
    M4(r, 0, 2) = s.z;
    M4(r, 1, 0) = u.x;
    M4(r, 1, 1) = u.y;
    M4(r, 1, 2) = u.z;
    M4(r, 2, 0) = -f.x;
    M4(r, 2, 1) = -f.y;
    M4(r, 2, 2) = -f.z;
    M4(r, 0, 3) = -geom_vec3_dot(s, eye);
    M4(r, 1, 3) = -geom_vec3_dot(u, eye);
    M4(r, 2, 3) = geom_vec3_dot(f, eye);
    if (out)
        *out = r;
    return GEOM_OK;
}

geom_status geom_mat4_perspective(double fovy, double aspect, double n, double f, geom_mat4 *out)
{
    if (!(fovy > 0.0 && fovy < GEOM_PI && aspect > 0.0 && n > 0.0 && f > n) || !isfinite(aspect) ||
        !isfinite(f)) {
        if (out)
            *out = geom_mat4_identity();
        return GEOM_ERR_DOMAIN;
    }
    double cot = 1.0 / tan(0.5 * fovy);
    geom_mat4 r = {{0}};
    M4(r, 0, 0) = cot / aspect;
    M4(r, 1, 1) = cot;
    M4(r, 2, 2) = (f + n) / (n - f);
    M4(r, 2, 3) = 2.0 * f * n / (n - f);
    M4(r, 3, 2) = -1.0;
    if (out)
        *out = r;
    return GEOM_OK;
}

geom_status geom_mat4_ortho(double l, double r, double b, double t, double n, double f,
                            geom_mat4 *out)
{
    if (!(isfinite(l) && isfinite(r) && isfinite(b) && isfinite(t) && isfinite(n) &&
          isfinite(f)) ||
        l == r || b == t || n == f) {
        if (out)
            *out = geom_mat4_identity();
        return GEOM_ERR_DOMAIN;
    }
    geom_mat4 m = geom_mat4_identity();
    M4(m, 0, 0) = 2.0 / (r - l);
    M4(m, 1, 1) = 2.0 / (t - b);
    M4(m, 2, 2) = -2.0 / (f - n);
    M4(m, 0, 3) = -(r + l) / (r - l);
    M4(m, 1, 3) = -(t + b) / (t - b);
    M4(m, 2, 3) = -(f + n) / (f - n);
    if (out)
        *out = m;
    return GEOM_OK;
}
