/*
 * libgeom bary: barycentric and generalized barycentric coordinates, and
 * attribute interpolation (including perspective-correct interpolation).
 *
 * Robustness contract for the simplex functions (triangle 2D/3D, tetrahedron):
 *  - every coordinate is the ratio of two determinants. A fast path evaluates
 *    them in floating point with a rigorous error bound and accepts a value
 *    only when its relative error is certified to be at most 2^-42; the
 *    determinants it cannot certify are evaluated exactly (expansion
 *    arithmetic) and rounded once. So each coordinate has a relative error of
 *    at most 2^-41 + 2^-53 (about 4.6e-13) of its own magnitude, and a few
 *    ulp where the exact path was taken, whatever the triangle's shape or the
 *    coordinates' offset from the origin;
 *  - signs are exact: a point exactly on an edge (face) gets exactly 0 for the
 *    opposite coordinate, a point exactly at a vertex gets exactly (1, 0, 0);
 *    a nonzero coordinate too small for a double is +-DBL_TRUE_MIN, one too
 *    large (a point extremely far from a tiny triangle) is +-Inf;
 *  - the coordinates are not renormalised to sum to 1; their sum is 1 within
 *    about 1e-12 of the largest coordinate (a few ulp on the exact path);
 *  - a zero-area triangle (zero-volume tetrahedron) returns
 *    GEOM_ERR_DEGENERATE and zero coordinates, never NaN; NaN/Inf input
 *    returns GEOM_ERR_INVALID_ARG and zero coordinates.
 * The fast path answers the well-conditioned cases (points not too close to
 * an edge of a not too thin simplex); the rest takes the exact path.
 */
#ifndef GEOM_BARY_H
#define GEOM_BARY_H

#include "geom/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Barycentric coordinates of p with respect to the 2D triangle (a, b, c):
 * p = l[0] a + l[1] b + l[2] c with l summing to 1. Each point is 2 doubles;
 * l receives 3 doubles. Either orientation of the triangle is accepted.
 * Returns GEOM_OK, GEOM_ERR_DEGENERATE (collinear vertices) or
 * GEOM_ERR_INVALID_ARG (NULL pointer or non-finite input).
 */
GEOM_API geom_status geom_bary_tri2(const double a[2], const double b[2], const double c[2],
                           const double p[2], double l[3]);

/**
 * Barycentric coordinates of the orthogonal projection of p onto the plane of
 * the 3D triangle (a, b, c); each point is 3 doubles, l receives 3 doubles.
 * l[i] = (n . n_i) / (n . n) with n = (b-a)x(c-a) and n_i the normal of the
 * sub-triangle opposite vertex i, with numerator and denominator (degree-4
 * polynomials in the input) certified or evaluated exactly as above. Same
 * statuses and guarantees as geom_bary_tri2.
 */
GEOM_API geom_status geom_bary_tri3(const double a[3], const double b[3], const double c[3],
                           const double p[3], double l[3]);

/**
 * Barycentric coordinates of p in the tetrahedron (a, b, c, d); l receives 4
 * doubles. GEOM_ERR_DEGENERATE for a coplanar tetrahedron.
 */
GEOM_API geom_status geom_bary_tet(const double a[3], const double b[3], const double c[3],
                          const double d[3], const double p[3], double l[4]);

/**
 * Mean value coordinates (Floater 2003; the formulation of Hormann and Floater
 * 2006, valid for arbitrary simple polygons, convex or not) of p with respect
 * to the polygon with n >= 3 vertices `poly` (2*n doubles, x0 y0 x1 y1 ...,
 * either orientation). w receives n doubles summing to 1 that reproduce p
 * (linear precision). Points exactly on an edge get the edge's linear
 * interpolation weights (others exactly 0); a vertex gets exactly 1 there.
 * Defined everywhere in the plane; accuracy ~1e-13 relative away from the
 * boundary. GEOM_ERR_DEGENERATE if the polygon has a zero-length edge or zero
 * area (all vertices collinear), or, for a self-intersecting polygon, if the
 * weights cancel; GEOM_ERR_INVALID_ARG for n < 3, NULL or non-finite input.
 */
GEOM_API geom_status geom_bary_mean_value(size_t n, const double *poly, const double p[2], double *w);

/**
 * Wachspress coordinates (Wachspress 1975; Meyer et al. 2002) of p inside the
 * strictly convex polygon `poly` (2*n doubles, either orientation); w receives
 * n doubles. Boundary points are handled exactly as in
 * geom_bary_mean_value. GEOM_ERR_DOMAIN if the polygon is not convex or p lies
 * outside it (w set to 0); GEOM_ERR_DEGENERATE for collinear consecutive
 * vertices.
 */
GEOM_API geom_status geom_bary_wachspress(size_t n, const double *poly, const double p[2], double *w);

/**
 * Interpolate k vertex attributes: out[j] = sum_i l[i] * attr[i*ncomp + j] for
 * j < ncomp, with k weights l (k doubles) and attr holding k*ncomp doubles.
 * GEOM_ERR_INVALID_ARG for NULL pointers or k == 0.
 */
GEOM_API geom_status geom_bary_interpolate(size_t k, const double *l, size_t ncomp, const double *attr,
                                  double *out);

/**
 * Perspective-correct weights: given screen-space barycentric coordinates l
 * (3 doubles) of a fragment and the clip-space w of the triangle's vertices
 * (3 doubles, all non-zero and of the same sign for a triangle in front of the
 * camera), compute the weights lp (3 doubles) with which attributes are
 * interpolated: lp[i] = (l[i]/w[i]) / sum_j (l[j]/w[j]), i.e. interpolating
 * a/w and 1/w linearly in screen space. GEOM_ERR_DEGENERATE if a w is zero or
 * the sum vanishes; GEOM_ERR_INVALID_ARG for non-finite input.
 */
GEOM_API geom_status geom_bary_perspective(const double l[3], const double w[3], double lp[3]);

/* ------------------------------------------------------------ batches */

/** Which simplex function geom_bary_simplex_many applies. */
typedef enum geom_bary_simplex {
    GEOM_BARY_TRI2 = 1, /**< geom_bary_tri2: points of 2 doubles, 3 weights */
    GEOM_BARY_TRI3 = 2, /**< geom_bary_tri3: points of 3 doubles, 3 weights */
    GEOM_BARY_TET = 3   /**< geom_bary_tet: points of 3 doubles, 4 weights */
} geom_bary_simplex;

/**
 * The simplex function `kind` over n rows in one call (for bindings and
 * loops over arrays; the results are those of the single-point function).
 * pts: the vertex arrays and the query point array, in the single
 * function's argument order (a, b, c, p for triangles; a, b, c, d, p for
 * tet; unused entries ignored); row i of argument j starts at pts[j] +
 * i * strides[j] (strides in doubles: the point size for one point per row,
 * 0 for the same point in every row). out: k*n doubles (k = 3 or 4).
 * status (n int32 values, NULL allowed) receives each row's geom_status;
 * a failing row's weights are NaN; *n_failed (NULL allowed) counts them.
 * Returns GEOM_OK (rows fail individually), or GEOM_ERR_INVALID_ARG for a
 * NULL array or a bad kind with n > 0 (nothing written).
 * One simplex shared by every row (all vertex strides 0) takes a faster
 * loop: tri2 gives bitwise the single function's results; tet evaluates
 * each determinant along the row of p (certified by the same filter), so a
 * weight may differ from geom_bary_tet's in the last bits, always within its
 * stated accuracy and with the same exact zeros, ones and statuses.
 */
GEOM_API geom_status geom_bary_simplex_many(geom_bary_simplex kind, size_t n,
                                            const double *const pts[5], const size_t strides[5],
                                            double *out, int32_t *status, size_t *n_failed);

/**
 * Mean value (wachspress == 0) or Wachspress coordinates of n points p
 * (2*n doubles) in one polygon of nv vertices (2*nv doubles); w receives
 * nv*n doubles, row by row. status / n_failed as geom_bary_simplex_many.
 * GEOM_ERR_INVALID_ARG for NULL arrays or nv < 3 with n > 0.
 */
GEOM_API geom_status geom_bary_polygon_many(int wachspress, size_t nv, const double *poly,
                                            size_t n, const double *p, double *w,
                                            int32_t *status, size_t *n_failed);

/**
 * geom_bary_perspective over n rows: row i uses l + i*sl and w + i*sw
 * (3 doubles each; a stride is 3 for one row per query, 0 for the same
 * values in every row) and writes lp[3*i .. 3*i+2]. Each row is computed
 * with geom_bary_perspective's operations (rows by blocks, vectorised; a row
 * that needs its rescaling or fails goes through it), so the weights are
 * bitwise its results. lp may be l (sl 3) but must not overlap it otherwise.
 * status / n_failed as geom_bary_simplex_many (a failing row's weights are
 * NaN: GEOM_ERR_DEGENERATE for a zero w or a vanishing sum,
 * GEOM_ERR_INVALID_ARG for non-finite input). Returns GEOM_OK, or
 * GEOM_ERR_INVALID_ARG for a NULL array with n > 0 (nothing written).
 */
GEOM_API geom_status geom_bary_perspective_many(size_t n, const double *l, size_t sl,
                                                const double *w, size_t sw, double *lp,
                                                int32_t *status, size_t *n_failed);

/**
 * geom_bary_interpolate over n rows of k weights (l: k*n doubles, row by
 * row) with one attribute table attr (k*ncomp doubles) shared by every row:
 * out (ncomp*n doubles) row i = sum_j l[k*i + j] * attr[j*ncomp + ...],
 * summed in the order of geom_bary_interpolate (bitwise its results).
 * GEOM_ERR_INVALID_ARG for NULL arrays or k == 0 with n > 0 (nothing
 * written); GEOM_OK otherwise (non-finite weights propagate as in IEEE
 * arithmetic, as in the single function).
 */
GEOM_API geom_status geom_bary_interpolate_many(size_t n, size_t k, const double *l,
                                                size_t ncomp, const double *attr, double *out);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_BARY_H */
