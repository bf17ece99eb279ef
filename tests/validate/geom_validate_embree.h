/*
 * geom_validate, Embree part: closest hits of rays on a triangle mesh from
 * Embree 3 (float, single thread: rtcNewDevice("threads=1")), in its default
 * mode or with RTC_SCENE_FLAG_ROBUST (watertight traversal and triangle
 * test). Rays are converted to float, as Embree does.
 */
#ifndef GEOM_VALIDATE_EMBREE_H
#define GEOM_VALIDATE_EMBREE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Closest hits of nr rays (rays: 6 doubles each, origin then direction,
 * t in [0, inf)) on the mesh positions (3*nv) / tris (3*nt). t_out: nr
 * doubles, NaN for a miss; prim_out (may be NULL): nr triangle indices
 * (UINT32_MAX for a miss). robust != 0 sets RTC_SCENE_FLAG_ROBUST.
 * Returns 0, or -1 if Embree failed (no device, bad buffers).
 */
int gv_embree_closest(const double *positions, size_t nv, const uint32_t *tris, size_t nt, int robust,
                      const double *rays, size_t nr, double *t_out, uint32_t *prim_out);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_VALIDATE_EMBREE_H */
