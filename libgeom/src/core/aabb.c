/* Axis-aligned boxes and the NaN-safe ray/box slab test. */
#include "core/internal.h"

#include <float.h>

geom_aabb geom_aabb_empty(void)
{
    geom_aabb b = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    return b;
}

bool geom_aabb_is_empty(geom_aabb b)
{
    /* Written so that NaN bounds also count as empty. */
    return !(b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z);
}

geom_aabb geom_aabb_extend(geom_aabb b, geom_vec3 p)
{
    b.min = geom_vec3_make(fmin(b.min.x, p.x), fmin(b.min.y, p.y), fmin(b.min.z, p.z));
    b.max = geom_vec3_make(fmax(b.max.x, p.x), fmax(b.max.y, p.y), fmax(b.max.z, p.z));
    return b;
}

geom_aabb geom_aabb_union(geom_aabb a, geom_aabb b)
{
    geom_aabb r;
    r.min = geom_vec3_make(fmin(a.min.x, b.min.x), fmin(a.min.y, b.min.y), fmin(a.min.z, b.min.z));
    r.max = geom_vec3_make(fmax(a.max.x, b.max.x), fmax(a.max.y, b.max.y), fmax(a.max.z, b.max.z));
    return r;
}

bool geom_aabb_contains(geom_aabb b, geom_vec3 p)
{
    return p.x >= b.min.x && p.x <= b.max.x && p.y >= b.min.y && p.y <= b.max.y &&
           p.z >= b.min.z && p.z <= b.max.z;
}

/* One slab: narrows [*t0, *t1]; returns false when the interval becomes empty
 * or the data are NaN. */
static bool slab(double o, double d, double lo, double hi, double *t0, double *t1)
{
    if (d == 0.0) /* parallel: inside iff the origin lies within the slab */
        return o >= lo && o <= hi;
    /* Division rather than a reciprocal: (lo - o) == 0 with a subnormal d
     * would otherwise give 0 * inf = NaN. */
    double tn = (lo - o) / d, tf = (hi - o) / d;
    if (tn > tf) {
        double t = tn;
        tn = tf;
        tf = t;
    }
    /* Ize 2013: widen by 2*gamma(3) relative so rounding never loses a
     * tangent hit (applied to both ends, whatever their sign). */
    const double g = 2.0 * (3.0 * DBL_EPSILON * 0.5) / (1.0 - 3.0 * DBL_EPSILON * 0.5);
    tn -= fabs(tn) * g;
    tf += fabs(tf) * g;
    /* Comparisons are false for NaN, so NaN never widens the interval. */
    if (!(tn <= tf))
        return false;
    if (tn > *t0)
        *t0 = tn;
    if (tf < *t1)
        *t1 = tf;
    return *t0 <= *t1;
}

bool geom_ray_aabb(const geom_ray *r, geom_aabb b, double *t0, double *t1)
{
    if (!r)
        return false;
    double lo = r->tmin, hi = r->tmax;
    if (!(lo <= hi))
        return false;
    if (!slab(r->origin.x, r->dir.x, b.min.x, b.max.x, &lo, &hi) ||
        !slab(r->origin.y, r->dir.y, b.min.y, b.max.y, &lo, &hi) ||
        !slab(r->origin.z, r->dir.z, b.min.z, b.max.z, &lo, &hi))
        return false;
    if (t0)
        *t0 = lo;
    if (t1)
        *t1 = hi;
    return true;
}
