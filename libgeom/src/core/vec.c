/* 2D, 3D and 4D vector operations in double precision. */
#include "core/internal.h"

#include <float.h>

geom_vec2 geom_vec2_make(double x, double y)
{
    geom_vec2 r = {x, y};
    return r;
}
geom_vec2 geom_vec2_add(geom_vec2 a, geom_vec2 b) { return geom_vec2_make(a.x + b.x, a.y + b.y); }
geom_vec2 geom_vec2_sub(geom_vec2 a, geom_vec2 b) { return geom_vec2_make(a.x - b.x, a.y - b.y); }
geom_vec2 geom_vec2_scale(geom_vec2 a, double s) { return geom_vec2_make(a.x * s, a.y * s); }
double geom_vec2_dot(geom_vec2 a, geom_vec2 b) { return a.x * b.x + a.y * b.y; }
double geom_vec2_cross(geom_vec2 a, geom_vec2 b) { return a.x * b.y - a.y * b.x; }
double geom_vec2_length(geom_vec2 a) { return hypot(a.x, a.y); }

geom_status geom_vec2_normalize(geom_vec2 a, geom_vec2 *out)
{
    geom_vec3 n;
    geom_status s = geom_vec3_normalize(geom_vec3_make(a.x, a.y, 0.0), &n);
    if (out)
        *out = geom_vec2_make(n.x, n.y);
    return s;
}

geom_vec3 geom_vec3_make(double x, double y, double z)
{
    geom_vec3 r = {x, y, z};
    return r;
}
geom_vec3 geom_vec3_add(geom_vec3 a, geom_vec3 b) { return geom_vec3_make(a.x + b.x, a.y + b.y, a.z + b.z); }
geom_vec3 geom_vec3_sub(geom_vec3 a, geom_vec3 b) { return geom_vec3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
geom_vec3 geom_vec3_scale(geom_vec3 a, double s) { return geom_vec3_make(a.x * s, a.y * s, a.z * s); }
geom_vec3 geom_vec3_neg(geom_vec3 a) { return geom_vec3_make(-a.x, -a.y, -a.z); }
geom_vec3 geom_vec3_lerp(geom_vec3 a, geom_vec3 b, double t)
{
    return geom_vec3_make(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.z + t * (b.z - a.z));
}
double geom_vec3_dot(geom_vec3 a, geom_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
geom_vec3 geom_vec3_cross(geom_vec3 a, geom_vec3 b)
{
    return geom_vec3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

/* Largest absolute component; the scale used to avoid overflow/underflow. */
static double max_abs3(geom_vec3 a)
{
    return fmax(fabs(a.x), fmax(fabs(a.y), fabs(a.z)));
}

double geom_vec3_length(geom_vec3 a)
{
    if (isnan(a.x) || isnan(a.y) || isnan(a.z))
        return NAN;
    double m = max_abs3(a);
    if (m == 0.0 || isinf(m))
        return m;
    /* Scale by a power of two (exact) so the sum of squares cannot overflow or
     * lose precision to underflow. */
    int e;
    frexp(m, &e);
    double x = ldexp(a.x, -e), y = ldexp(a.y, -e), z = ldexp(a.z, -e);
    return ldexp(sqrt(x * x + y * y + z * z), e);
}

geom_status geom_vec3_normalize(geom_vec3 a, geom_vec3 *out)
{
    geom_vec3 zero = {0.0, 0.0, 0.0};
    if (!(isfinite(a.x) && isfinite(a.y) && isfinite(a.z))) {
        if (out)
            *out = zero;
        return GEOM_ERR_INVALID_ARG;
    }
    double m = max_abs3(a);
    if (m == 0.0) {
        if (out)
            *out = zero;
        return GEOM_ERR_DEGENERATE;
    }
    int e;
    frexp(m, &e);
    geom_vec3 s = geom_vec3_make(ldexp(a.x, -e), ldexp(a.y, -e), ldexp(a.z, -e));
    double len = sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
    if (out)
        *out = geom_vec3_make(s.x / len, s.y / len, s.z / len);
    return GEOM_OK;
}

geom_vec3 geom_vec3_reflect(geom_vec3 i, geom_vec3 n)
{
    return geom_vec3_sub(i, geom_vec3_scale(n, 2.0 * geom_vec3_dot(n, i)));
}

geom_status geom_vec3_refract(geom_vec3 i, geom_vec3 n, double eta, geom_vec3 *out)
{
    geom_vec3 zero = {0.0, 0.0, 0.0};
    if (!(isfinite(i.x) && isfinite(i.y) && isfinite(i.z) && isfinite(n.x) && isfinite(n.y) &&
          isfinite(n.z) && isfinite(eta)) ||
        !(eta > 0.0)) {
        if (out)
            *out = zero;
        return GEOM_ERR_INVALID_ARG;
    }
    double cosi = -geom_vec3_dot(n, i);
    /* sin^2 of the transmitted angle; written as eta^2 (1 - cos^2) with
     * (1 - c)(1 + c) to keep accuracy at grazing incidence. */
    double sin2t = eta * eta * ((1.0 - cosi) * (1.0 + cosi));
    if (sin2t > 1.0) {
        if (out)
            *out = geom_vec3_reflect(i, n);
        return GEOM_ERR_DOMAIN;
    }
    double cost = sqrt(1.0 - sin2t);
    if (out)
        *out = geom_vec3_add(geom_vec3_scale(i, eta), geom_vec3_scale(n, eta * cosi - cost));
    return GEOM_OK;
}

geom_vec4 geom_vec4_make(double x, double y, double z, double w)
{
    geom_vec4 r = {x, y, z, w};
    return r;
}

geom_status geom_vec4_homogeneous_divide(geom_vec4 a, geom_vec3 *out)
{
    if (a.w == 0.0 || !isfinite(a.w)) {
        if (out)
            *out = geom_vec3_make(0.0, 0.0, 0.0);
        return a.w == 0.0 ? GEOM_ERR_DEGENERATE : GEOM_ERR_INVALID_ARG;
    }
    if (out)
        *out = geom_vec3_make(a.x / a.w, a.y / a.w, a.z / a.w);
    return GEOM_OK;
}
