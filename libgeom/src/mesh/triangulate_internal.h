/*
 * Internal entry points of polygon triangulation, shared by triangulate.c
 * (ear clipping, the public functions) and triangulate_sweep.c (monotone
 * decomposition). Not installed.
 */
#ifndef GEOM_MESH_TRIANGULATE_INTERNAL_H
#define GEOM_MESH_TRIANGULATE_INTERNAL_H

#include "geom/core.h"

#include <stddef.h>
#include <stdint.h>

/* The ear clipper alone (the documented behaviour of geom_polygon_triangulate
 * before the sweep, kept for n <= 64 and as the fallback): same arguments
 * and statuses as geom_polygon_triangulate. */
geom_status geom__polygon_earclip(size_t n, const double *pts, uint32_t *tris);

/* Monotone-decomposition triangulation of the polygon whose projected
 * coordinates are (pts[3*i + u], pts[3*i + v]), i < n, n >= 3, all finite,
 * in either orientation. Writes n-2 triangles to tris (3*(n-2) indices),
 * each with the polygon's own winding, and returns GEOM_OK; GEOM_ERR_NOMEM;
 * GEOM_ERR_DEGENERATE when the sweep rejects the polygon (not simple, or a
 * degenerate shape it cannot order): tris is then unspecified and the caller
 * falls back to ear clipping. */
geom_status geom__polygon_triangulate_sweep(size_t n, const double *pts, int u, int v,
                                            uint32_t *tris);

/* As above, also saying how many monotone pieces were handed to the ear
 * clipper because the stack triangulation would have made a triangle that is
 * not strictly positive (for tests and benchmarks; may be NULL). */
geom_status geom__polygon_triangulate_sweep_ex(size_t n, const double *pts, int u, int v,
                                               uint32_t *tris, size_t *n_piece_fallbacks);

#endif
