/*
 * Private kernels of the surface module. Not installed.
 *
 * The span functions do no argument checking: callers check the surface
 * once (geom__surface_check_cheap or geom_surface_validate) and locate the
 * spans, then call them in inner loops with caller-provided work memory
 * (sizes from the matching *_work functions; geom__scratch gives a
 * stack buffer with a heap fallback).
 */
#ifndef GEOM_SRC_SURFACE_INTERNAL_H
#define GEOM_SRC_SURFACE_INTERNAL_H

#include "core/bspline.h"
#include "geom/curve.h"
#include "geom/surface.h"

/** Largest derivative order geom_surface_derivs accepts. */
#define GEOM_SURFACE_MAX_DERIV 64
/** Highest total derivative order the limit normal looks at. */
#define GEOM_SURFACE_NORMAL_ORDER 9

/** Non-NULL arrays, degrees >= 1, counts >= degree+1. */
geom_status geom__surface_check_cheap(const geom_nurbs_surface *s);

/**
 * Check (u, v) and find the spans: NaN/Inf -> GEOM_ERR_INVALID_ARG, outside
 * the domain -> GEOM_ERR_DOMAIN; flags GEOM_SURFACE_U_LEFT/V_LEFT.
 */
geom_status geom__surface_locate(const geom_nurbs_surface *s, double u, double v, unsigned flags,
                                size_t *ku, size_t *kv);

/** Doubles of work for geom__surface_span_point. */
size_t geom__surface_point_work(const geom_nurbs_surface *s);

/** S(u, v) on spans (ku, kv) (A3.5/A4.3, exact control points where the
 *  basis is one-hot). */
void geom__surface_span_point(const geom_nurbs_surface *s, size_t ku, size_t kv, double u,
                             double v, double out[3], double *work);

/** The point of geom__surface_span_point from its basis values (Nu: p+1,
 *  Nv: q+1, from geom__bs_basis on spans ku, kv): the same result, for
 *  callers that evaluate a lattice and reuse each direction's basis. */
void geom__surface_span_combine(const geom_nurbs_surface *s, size_t ku, size_t kv, const double *Nu,
                               const double *Nv, double out[3]);

/** Doubles of work for geom__surface_span_derivs with order d. */
size_t geom__surface_derivs_work(const geom_nurbs_surface *s, int d);

/**
 * All S^(k,l), k + l <= d, on spans (ku, kv): ders[3*(k*(d+1)+l)], zero for
 * k + l > d. Derivatives from control points relative to the span's first
 * control point; S^(0,0) from geom__surface_span_point.
 */
void geom__surface_span_derivs(const geom_nurbs_surface *s, size_t ku, size_t kv, double u,
                              double v, int d, double *ders, double *work);

/** Doubles of work for geom__surface_span_normal. */
size_t geom__surface_normal_work(const geom_nurbs_surface *s);

/**
 * Unit normal on spans (ku, kv) at (u, v) (see geom_surface_normal); su, sv
 * in {-1, +1}: the directions toward the interior of the region the point
 * belongs to (the domain, or a tessellation cell). tangent (NULL allowed)
 * receives the unit direction of dP/du (its limit at a degenerate point; if
 * dP/du vanishes along the whole approach, a unit vector perpendicular to
 * the normal in the plane it spans with dP/dv). Returns GEOM_SURFACE_NORMAL_*;
 * n (and tangent) are zero for GEOM_SURFACE_NORMAL_NONE.
 */
int geom__surface_span_normal(const geom_nurbs_surface *s, size_t ku, size_t kv, double u, double v,
                             int su, int sv, double n[3], double tangent[3], double *work);

/* The surface module's per-patch triangle estimate (tess_estimate.c),
 * shared with the STEP faces' (step/estimate.c): fn gives |S_uu|, |S_uv|,
 * |S_vv| at (u, v) (returns 0 where undefined); the triangles a flat
 * tessellation within tol needs over the parameter box dom (u0 u1 v0 v1),
 * sampled at the centres of a gu x gv grid, each sample cell counting at
 * least floor_count triangles per direction (1 where the tessellator
 * starts from a grid, 0 where it adds interior points only as needed). */
typedef int (*geom__second_derivs_fn)(void *user, double u, double v, double out[3]);
double geom__tess_estimate_grid(geom__second_derivs_fn fn, void *user, const double dom[4],
                                size_t gu, size_t gv, double tol, double floor_count);

/* Lines of constant parameter for the tessellator's segment-count bounds
 * (tess_lines.c): fn(user, l, t, out) is the point of line l (0..nlines-1)
 * at parameter t in [a, b]. geom__tess_lines_pass: does every segment of
 * the n-segment polylines (uniform in t) keep its K-1 side samples (at
 * fractions m/K of the segment's parameter range) within tol of its chord,
 * as point-segment distances? *hint (NAN: none) is a parameter whose
 * segment is tested first; it receives the parameter of a failing sample.
 * geom__tess_lines_bound: the smallest n in [1, cap) that passes, else cap:
 * the answer of testing n = 1, 2, ... in turn (no monotonicity assumed),
 * each failing n usually shown by one segment. */
typedef void (*geom__tess_line_fn)(void *user, int line, double t, double out[3]);
int geom__tess_lines_pass(geom__tess_line_fn fn, void *user, int nlines, double a, double b, int K,
                          uint32_t n, double tol, double *hint);
uint32_t geom__tess_lines_bound(geom__tess_line_fn fn, void *user, int nlines, double a, double b,
                                int K, uint32_t cap, double tol);

/* Non-uniform grid lines of a tessellation cell (tess_warp.c): from rho,
 * sqrt of the second derivative normal to the lines' tangent sampled on n
 * equal parameter intervals, F (n+1 doubles): the line density's integral
 * at the interval ends, normalised to F[0] = 0, F[n] = 1, each interval's
 * density at least floor_frac times the mean. Returns 0 (F unset: keep the
 * lines uniform) when rho is not finite, all zero, or its largest value is
 * at most ratio times its smallest. geom__tess_warp_y: the parameter
 * fraction y of grid fraction f (the inverse of F, piecewise linear, exact
 * 0 and 1 at the ends); geom__tess_warp_f: F at parameter fraction y. */
int geom__tess_warp_build(const double *rho, int n, double ratio, double floor_frac, double *F);
double geom__tess_warp_y(const double *F, int n, double f);
double geom__tess_warp_f(const double *F, int n, double y);

#endif
