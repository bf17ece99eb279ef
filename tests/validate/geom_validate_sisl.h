/*
 * geom_validate, SISL part: reference B-spline and NURBS evaluation from
 * SINTEF's SISL 4.6 (Debian libsisl-dev), for the curve and surface tests
 * and benchmarks.
 *
 * SISL keeps its own layouts; these functions take libgeom's:
 *  - curves: n control points of `dim` doubles (Euclidean), weights NULL or
 *    n values > 0, knots n + degree + 1;
 *  - surfaces: control point (i, j) (i along u) at 3*(i*nv + j), weight at
 *    i*nv + j.
 * and convert: SISL orders surface coefficients with the first parameter
 * running fastest (index j*nu + i) and takes rational coefficients in
 * homogeneous form (w*x, w*y, w*z, w).
 *
 * Evaluation: s1221 (curves, right-continuous: at a knot the span to its
 * right, at the end of the domain the last span), s1227 (curves, left
 * limits), s1421 (surfaces, all S^(k,l) with k + l <= d, right-continuous
 * in both directions). SISL computes rational derivatives with its own
 * quotient rule (s6ratder / s6strider).
 *
 * SISL is a static, non-PIC library: only test and benchmark programs
 * link this part. Nothing here prints, throws across the C interface or
 * keeps global state.
 */
#ifndef GEOM_VALIDATE_SISL_H
#define GEOM_VALIDATE_SISL_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define GV_SISL_OK 0
#define GV_SISL_ERR_INVALID (-1) /**< NULL pointer, bad size or degree, NaN/Inf */
#define GV_SISL_ERR_SISL (-2)    /**< SISL returned a negative status */
#define GV_SISL_ERR_INTERNAL (-3) /**< out of memory (an exception was caught) */

/**
 * Point and derivatives 0..nderiv of a B-spline (weights NULL) or NURBS
 * curve at u: ders receives (nderiv+1)*dim doubles, derivative k at
 * [k*dim, (k+1)*dim). left == 0 uses s1221 (right limit), left != 0 s1227
 * (left limit). dim 1..4, degree >= 1, n >= degree + 1. u must lie in the
 * domain [knots[degree], knots[n]]. Returns GV_SISL_OK or an error code
 * (ders zeroed).
 */
int gv_sisl_curve_derivs(int degree, size_t n, size_t dim, const double *knots,
                         const double *points, const double *weights, double u, int nderiv,
                         int left, double *ders);

/** A prepared SISL surface (for repeated evaluation, e.g. benchmarks). */
typedef struct gv_sisl_surface gv_sisl_surface;

/**
 * Convert a B-spline (weights NULL) or NURBS surface in libgeom's layout
 * into a SISL surface (the arrays are copied). NULL on bad input or out of
 * memory.
 */
gv_sisl_surface *gv_sisl_surface_create(int degree_u, int degree_v, size_t nu, size_t nv,
                                        const double *knots_u, const double *knots_v,
                                        const double *points, const double *weights);

/** Free a prepared surface; NULL is a no-op. */
void gv_sisl_surface_destroy(gv_sisl_surface *s);

/**
 * s1421 at (u, v): all partial derivatives S^(k,l), k + l <= d (d >= 0),
 * in libgeom's layout: ders receives 3*(d+1)*(d+1) doubles, S^(k,l) at
 * 3*(k*(d+1) + l), entries with k + l > d zero. Returns GV_SISL_OK or an
 * error code.
 */
int gv_sisl_surface_eval(gv_sisl_surface *s, double u, double v, int d, double *ders);

/**
 * s1421 returning only the point (d = 0) into p (3 doubles), without any
 * layout conversion: the cheapest call, for throughput comparisons.
 */
int gv_sisl_surface_point(gv_sisl_surface *s, double u, double v, double *p);

/**
 * s1856: every intersection point of the line point + t dir (3 doubles
 * each) with the surface, as parameter pairs (u, v) into params (2*cap
 * doubles), *n the number found (may exceed cap). eps: SISL's geometric
 * tolerance. Returns GV_SISL_OK, or GV_SISL_ERR_SISL when SISL failed or
 * found intersection curves (the line lies in the surface).
 */
int gv_sisl_line_surface(gv_sisl_surface *s, const double point[3], const double dir[3], double eps,
                         double *params, size_t cap, size_t *n);

/** One-shot: create, evaluate, destroy. */
int gv_sisl_surface_derivs(int degree_u, int degree_v, size_t nu, size_t nv,
                           const double *knots_u, const double *knots_v, const double *points,
                           const double *weights, double u, double v, int d, double *ders);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_VALIDATE_SISL_H */
