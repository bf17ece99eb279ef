/*
 * geom_validate, spatial part: closest points on a triangle mesh from CGAL's
 * AABB_tree (Simple_cartesian<double>, AABB_triangle_primitive, with
 * accelerate_distance_queries), for the spatial tests.
 *
 * Nothing here prints, throws across the C interface (exceptions become
 * GV_SPATIAL_ERR) or keeps global state.
 */
#ifndef GEOM_VALIDATE_SPATIAL_H
#define GEOM_VALIDATE_SPATIAL_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define GV_SPATIAL_OK 0
#define GV_SPATIAL_ERR (-1)

/**
 * For each of nq queries (3*nq doubles), the closest point on the mesh
 * (positions 3*nv doubles, tris 3*nt indices) as CGAL's AABB_tree computes
 * it: point (3*nq doubles, may be NULL), the triangle it lies on (tri, nq
 * entries, may be NULL) and the squared distance (d2, nq entries, may be
 * NULL). Returns GV_SPATIAL_OK, or GV_SPATIAL_ERR (empty mesh, bad index,
 * exception).
 */
int gv_spatial_closest(const double *positions, size_t nv, const uint32_t *tris, size_t nt,
                       const double *queries, size_t nq, double *point, uint32_t *tri, double *d2);

#ifdef __cplusplus
}
#endif

#endif
