/* The watertight ray/triangle test (Woop, Benthin and Wald, "Watertight
 * Ray/Triangle Intersection", JCGT 2013) in double, with exact edge-function
 * signs and an edge-ownership rule for zero edge functions. Static inline so
 * that the mesh traversal (mesh.c) and the single-triangle and polygon
 * queries (triangle.c) share one definition without a call per triangle.
 * Private to the ray module. */
#ifndef GEOM_SRC_RAY_WBW_H
#define GEOM_SRC_RAY_WBW_H

#include "ray/ray_internal.h"

/* orient(O, P, Q) = Px Qy - Py Qx with an exact sign (Shewchuk's
 * predicate when the double value is within its error bound); exactly
 * antisymmetric in P, Q. */
static inline double geom__wbw_edge(double px, double py, double qx, double qy)
{
    double a = px * qy, b = py * qx, e = a - b;
    if (fabs(e) <= 4 * DBL_EPSILON * (fabs(a) + fabs(b))) {
        double O[2] = {0, 0}, P[2] = {px, py}, Q[2] = {qx, qy};
        e = geom_orient2d(O, P, Q);
    }
    return e;
}

/* Whether the directed edge P -> Q owns a zero edge function. */
static inline int geom__wbw_owns(double px, double py, double qx, double qy)
{
    double dy = qy - py, dx = qx - px;
    return dy > 0 || (dy == 0 && dx > 0);
}

/* 1 on a hit with t in [tmin, tmax]; fills t and b (barycentrics of v0, v1,
 * v2). The sheared vertex coordinates depend only on the vertex and the ray,
 * and the edge functions are exactly antisymmetric, so an edge shared by two
 * triangles is crossed by exactly one of them. */
#if defined(__GNUC__) || defined(__clang__)
#define GEOM__WBW_INLINE static inline __attribute__((always_inline))
#else
#define GEOM__WBW_INLINE static inline
#endif
/* geom__wbw_hit with the ray's axes given (kx, ky, kz == w->kx, w->ky,
 * w->kz): a caller that dispatches once per ray on the axes passes
 * constants, and the permutation costs nothing per triangle. */
GEOM__WBW_INLINE int geom__wbw_hit_k(const geom__wbw *w, const int kx, const int ky, const int kz,
                                  const double *v0, const double *v1, const double *v2,
                                  double tmin, double tmax, double *t, double *b)
{
    /* Vertices relative to the origin, component by component (no arrays:
     * stored one double at a time and reloaded two at a time, they would
     * stall store forwarding). */
    const double ox = w->o[kx], oy = w->o[ky], oz = w->o[kz];
    const double Az = v0[kz] - oz, Bz = v1[kz] - oz, Cz = v2[kz] - oz;
    double ax, ay, bx, by, cx, cy, e0, e1, e2, det, az, bz, cz, T;
    int pos, neg;
    ax = (v0[kx] - ox) - w->sx * Az; ay = (v0[ky] - oy) - w->sy * Az;
    bx = (v1[kx] - ox) - w->sx * Bz; by = (v1[ky] - oy) - w->sy * Bz;
    cx = (v2[kx] - ox) - w->sx * Cz; cy = (v2[ky] - oy) - w->sy * Cz;
    e0 = geom__wbw_edge(bx, by, cx, cy); /* edge v1 -> v2: weight of v0 */
    e1 = geom__wbw_edge(cx, cy, ax, ay); /* edge v2 -> v0: weight of v1 */
    if ((e0 < 0 && e1 > 0) || (e0 > 0 && e1 < 0)) return 0; /* the common miss */
    e2 = geom__wbw_edge(ax, ay, bx, by); /* edge v0 -> v1: weight of v2 */
    if ((e2 < 0 && (e0 > 0 || e1 > 0)) || (e2 > 0 && (e0 < 0 || e1 < 0))) return 0;
    /* Front (all >= 0) or back (all <= 0) facing, a zero only where owned. */
    if (e0 == 0 || e1 == 0 || e2 == 0) {
        pos = (e0 > 0 || (e0 == 0 && geom__wbw_owns(bx, by, cx, cy))) &&
              (e1 > 0 || (e1 == 0 && geom__wbw_owns(cx, cy, ax, ay))) &&
              (e2 > 0 || (e2 == 0 && geom__wbw_owns(ax, ay, bx, by)));
        neg = (e0 < 0 || (e0 == 0 && geom__wbw_owns(bx, by, cx, cy))) &&
              (e1 < 0 || (e1 == 0 && geom__wbw_owns(cx, cy, ax, ay))) &&
              (e2 < 0 || (e2 == 0 && geom__wbw_owns(ax, ay, bx, by)));
        if (!pos && !neg) return 0;
    }
    det = e0 + e1 + e2;
    if (det == 0 || !isfinite(det)) return 0;
    az = w->sz * Az; bz = w->sz * Bz; cz = w->sz * Cz;
    T = e0 * az + e1 * bz + e2 * cz;
    *t = T / det;
    if (!(*t >= tmin && *t <= tmax)) return 0;
    b[0] = e0 / det;
    b[1] = e1 / det;
    b[2] = e2 / det;
    return 1;
}

GEOM__WBW_INLINE int geom__wbw_hit(const geom__wbw *w, const double *v0, const double *v1, const double *v2,
                                double tmin, double tmax, double *t, double *b)
{
    return geom__wbw_hit_k(w, w->kx, w->ky, w->kz, v0, v1, v2, tmin, tmax, t, b);
}

#endif
