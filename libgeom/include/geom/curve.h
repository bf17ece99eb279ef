/*
 * libgeom curve: cubic Hermite segments and splines, Catmull-Rom and
 * Kochanek-Bartels splines, Bezier curves of any degree, B-spline and NURBS
 * curves (evaluation, derivatives, knot insertion, refinement, removal,
 * degree elevation, Bezier decomposition), exact conics, arc length, closest
 * point, curvature and torsion, and adaptive polylines.
 *
 * References: L. Piegl and W. Tiller, The NURBS Book, 2nd ed., Springer 1997
 * (algorithm numbers A2.1 ... A7.1 below are theirs); G. Farin, Curves and
 * Surfaces for CAGD; P. Barry and R. Goldman, "A recursive evaluation
 * algorithm for a class of Catmull-Rom splines", SIGGRAPH 1988; C. Yuksel,
 * S. Schaefer and J. Keyser, "Parameterization and applications of
 * Catmull-Rom curves", CAD 43(7), 2011; D. Kochanek and R. Bartels,
 * "Interpolating splines with local tension, continuity, and bias control",
 * SIGGRAPH 1984.
 *
 * Conventions:
 *  - A point is `dim` doubles, 1 <= dim <= GEOM_CURVE_MAX_DIM (typically 2
 *    or 3). An array of n points is n*dim contiguous doubles, point i at
 *    [i*dim, (i+1)*dim).
 *  - Rational curves take their weights as a separate array (n doubles,
 *    each finite and > 0); points are Euclidean, NOT multiplied by the
 *    weight. Internally the algorithms work on homogeneous points (w*P, w).
 *  - Outputs are caller-owned buffers whose sizes are given in each comment
 *    (or by a *_bound() function); outputs must not overlap inputs.
 *  - Every function returns geom_status: GEOM_OK, or GEOM_ERR_INVALID_ARG
 *    for NULL where not allowed, a bad size, or a NaN/Inf number;
 *    GEOM_ERR_DOMAIN for a finite argument outside the function's domain;
 *    other statuses where listed. On failure the outputs are unspecified
 *    unless the comment says otherwise. Functions that take a `geom_diag *`
 *    (NULL allowed) also put a one-line reason there.
 *  - Nothing prints or keeps global state; every function is reentrant.
 *    Functions whose scratch grows with the degree use an 8 KiB stack
 *    buffer and fall back to the C library's malloc when it is too small
 *    (derivatives above degree ~29, the closest-point search for cubics and
 *    up); they can then return GEOM_ERR_NOMEM.
 *
 * B-spline and NURBS curves (geom_nurbs_curve): n control points, degree p
 * >= 1, n >= p+1, knots u_0 <= ... <= u_{n+p} (n+p+1 doubles), no knot value
 * repeated more than p+1 times, u_p < u_n. The parameter domain is
 * [u_p, u_n]. This covers clamped knot vectors (u_0 = ... = u_p and
 * u_n = ... = u_{n+p}: the curve interpolates its first and last points),
 * unclamped ones (any other knots outside the domain), and periodic curves,
 * which are unclamped curves with uniform knot spacing whose last p control
 * points repeat the first p (see geom_curve_nurbs_periodic). Use
 * geom_curve_nurbs_validate() on untrusted input: the evaluation functions
 * check only the cheap things (pointers, sizes, the parameter) and on knots
 * or weights that violate the rules above give unspecified (but memory-safe)
 * results.
 *
 * Rule at knots. Inside the domain a curve is evaluated as the right limit:
 * at a knot u_k the span [u_k, u_{k+1}) is used. With GEOM_CURVE_LEFT_LIMIT the
 * left limit is used (span (u_{k-1}, u_k]). The two differ only where the
 * curve or a derivative is discontinuous (multiplicity p+1 for the point,
 * multiplicity m for derivatives of order > p-m). At the ends of the domain
 * only one side exists and it is used whatever the flag: u == u_n is the left
 * limit, u == u_p the right limit. A clamped curve gives its first and last
 * control points exactly (bit for bit) at u_p and u_n, and a knot of
 * multiplicity >= p gives the corresponding control point exactly.
 */
#ifndef GEOM_CURVE_H
#define GEOM_CURVE_H

#include "geom/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Largest supported point dimension. */
#define GEOM_CURVE_MAX_DIM 4

/* geom_error_report and GEOM_ERROR_BOUND / _SAMPLED / _ESTIMATE come from
 * geom/core.h. */

/* -------------------------------------------------------------- evaluation */

/** Evaluation flags (bitwise or). 0 is the default: right limits, no wrap. */
enum {
    /** Use the left limit at a knot (see the rule at knots above). */
    GEOM_CURVE_LEFT_LIMIT = 1u << 0,
    /** Periodic evaluation: reduce u into [u_p, u_n) modulo the domain
     *  length before evaluating (with GEOM_CURVE_LEFT_LIMIT, a u that reduces
     *  to u_p is evaluated as the left limit at u_n). Without it, u outside
     *  the domain is GEOM_ERR_DOMAIN. */
    GEOM_CURVE_WRAP = 1u << 1
};

/**
 * A B-spline (weights == NULL) or NURBS curve; all arrays are borrowed.
 *   knots:   n + degree + 1 doubles;
 *   points:  n*dim doubles (Euclidean);
 *   weights: NULL for a polynomial B-spline, else n doubles > 0.
 */
typedef struct geom_nurbs_curve {
    int degree;
    size_t n;   /**< number of control points */
    size_t dim; /**< 1 .. GEOM_CURVE_MAX_DIM */
    const double *knots;
    const double *points;
    const double *weights;
} geom_nurbs_curve;

/* ---------------------------------------------------------- Hermite curves */

/**
 * Bezier control points of the cubic Hermite segment with end points p0, p1
 * and end derivatives m0, m1 (with respect to t in [0, 1]): b0 = p0,
 * b1 = p0 + m0/3, b2 = p1 - m1/3, b3 = p1. Each input is dim doubles;
 * bezier receives 4*dim doubles. Exact up to one rounding per operation.
 */
GEOM_API geom_status geom_curve_hermite_to_bezier(size_t dim, const double *p0, const double *m0,
                                         const double *p1, const double *m1, double *bezier);

/**
 * Point and derivatives 0..nderiv (nderiv >= 0) of the cubic Hermite segment
 * at t (any finite t; [0, 1] is the segment), through its Bezier form and de
 * Casteljau's algorithm. ders receives (nderiv+1)*dim doubles (derivative k
 * at [k*dim, (k+1)*dim); orders above 3 are zero).
 */
GEOM_API geom_status geom_curve_hermite_eval(size_t dim, const double *p0, const double *m0,
                                    const double *p1, const double *m1, double t, int nderiv,
                                    double *ders);

/**
 * Piecewise cubic Hermite spline through n >= 2 points with the given
 * derivatives, as 3*(n-1)+1 Bezier control points (segment i is
 * bezier[3i .. 3i+3], consecutive segments share their end point).
 * points, tangents: n*dim doubles, tangents are derivatives with respect to
 * the global parameter; params: n strictly increasing finite values, or NULL
 * for 0, 1, ..., n-1. Segment i covers [params[i], params[i+1]] and its
 * inner control points are P_i + h m_i/3 and P_{i+1} - h m_{i+1}/3 with
 * h = params[i+1] - params[i]. With geom_curve_piecewise_bezier_knots() the
 * result is a cubic B-spline that reproduces the spline exactly (C1).
 * GEOM_ERR_DOMAIN if params are not strictly increasing.
 */
GEOM_API geom_status geom_curve_hermite_spline_to_bezier(size_t dim, size_t n, const double *points,
                                                const double *tangents, const double *params,
                                                double *bezier);

/**
 * Knot vector that turns nseg >= 1 Bezier segments of degree p >= 1 sharing
 * end points (nseg*p + 1 control points) into one B-spline: p+1 copies of
 * params[0], p copies of each interior params[i], p+1 copies of
 * params[nseg]. params: nseg+1 strictly increasing finite values, or NULL
 * for 0, 1, ..., nseg. knots receives nseg*p + p + 2 doubles.
 */
GEOM_API geom_status geom_curve_piecewise_bezier_knots(int degree, size_t nseg, const double *params,
                                              double *knots);

/** How Catmull-Rom and Kochanek-Bartels splines treat their end points. */
typedef enum geom_curve_end {
    /** Default: pass through every point; the missing neighbours of the
     *  first and last points are the reflections P_{-1} = 2 P_0 - P_1 and
     *  P_n = 2 P_{n-1} - P_{n-2}. n >= 2 points give n-1 segments. */
    GEOM_CURVE_END_EXTRAPOLATE = 0,
    /** The first and last points only shape the end segments: n >= 4
     *  points give n-3 segments from P_1 to P_{n-2}. */
    GEOM_CURVE_END_EXCLUDE = 1,
    /** Closed curve: indices wrap; n >= 3 points give n segments, the last
     *  from P_{n-1} back to P_0. */
    GEOM_CURVE_END_CLOSED = 2
} geom_curve_end;

/** Number of segments of a Catmull-Rom or Kochanek-Bartels spline of n
 *  points with the given end treatment (see geom_curve_end).
 *  GEOM_ERR_INVALID_ARG if n is too small for that treatment. */
GEOM_API geom_status geom_curve_catmull_rom_segments(size_t n, geom_curve_end ends, size_t *nseg);

/**
 * One Catmull-Rom segment from p1 to p2 (neighbours p0, p3) evaluated
 * directly by the Barry-Goldman pyramid with knots t0 = 0,
 * t_{i+1} = t_i + |P_{i+1} - P_i|^alpha; s in [0, 1] maps to [t1, t2].
 * alpha = 0 uniform, 0.5 centripetal, 1 chordal (any alpha in [0, 1]).
 * GEOM_ERR_DEGENERATE if alpha > 0 and two consecutive points coincide.
 * out: dim doubles. Accuracy: a few ulp of the point magnitudes.
 */
GEOM_API geom_status geom_curve_catmull_rom_eval(size_t dim, const double *p0, const double *p1,
                                        const double *p2, const double *p3, double alpha, double s,
                                        double *out);

/**
 * Exact cubic Bezier form of the Catmull-Rom spline through n points
 * (n*dim doubles) with parameterisation exponent alpha in [0, 1] (0
 * uniform, 0.5 centripetal, 1 chordal). The tangent at P_i is the
 * derivative of the Barry-Goldman curve,
 *   m_i = (P_i - P_{i-1})/d_{i-1} - (P_{i+1} - P_{i-1})/(d_{i-1} + d_i)
 *         + (P_{i+1} - P_i)/d_i,   d_i = |P_{i+1} - P_i|^alpha,
 * so each segment equals the Barry-Goldman segment (Yuksel et al. 2011) and
 * the spline is C1 in the Catmull-Rom parameter.
 * bezier: (3*nseg+1)*dim doubles (nseg from geom_curve_catmull_rom_segments).
 * params: NULL or nseg+1 doubles receiving the parameter of each joint
 * (cumulative d_i starting at 0); with geom_curve_piecewise_bezier_knots(3,
 * nseg, params, knots) the result is a C1 cubic B-spline.
 * GEOM_ERR_DEGENERATE (with a reason in diag) if alpha > 0 and two
 * consecutive points coincide.
 */
GEOM_API geom_status geom_curve_catmull_rom_to_bezier(size_t dim, size_t n, const double *points,
                                             double alpha, geom_curve_end ends, double *bezier,
                                             double *params, geom_diag *diag);

/** Tension, continuity and bias of a Kochanek-Bartels key (0, 0, 0 is
 *  Catmull-Rom). */
typedef struct geom_kb_params {
    double tension;
    double continuity;
    double bias;
} geom_kb_params;

/**
 * Exact cubic Bezier form of the Kochanek-Bartels spline through n points
 * with uniform parameterisation (segment i covers [i, i+1]). At P_i the
 * outgoing and incoming tangents are
 *   out_i = (1-t)(1+b)(1+c)/2 (P_i - P_{i-1}) + (1-t)(1-b)(1-c)/2 (P_{i+1} - P_i)
 *   in_i  = (1-t)(1+b)(1-c)/2 (P_i - P_{i-1}) + (1-t)(1-b)(1+c)/2 (P_{i+1} - P_i)
 * (segment i runs from P_i with out_i to P_{i+1} with in_{i+1}).
 * tcb: ntcb entries: ntcb == 0 (tcb may be NULL) means all zero (uniform
 * Catmull-Rom), 1 means the same for every point, n means one per point.
 * bezier: (3*nseg+1)*dim doubles. All parameters must be finite.
 */
GEOM_API geom_status geom_curve_kochanek_bartels_to_bezier(size_t dim, size_t n, const double *points,
                                                  const geom_kb_params *tcb, size_t ntcb,
                                                  geom_curve_end ends, double *bezier,
                                                  geom_diag *diag);

/* ----------------------------------------------------------- Bezier curves */

/**
 * Point of the Bezier curve of degree p >= 0 with p+1 control points
 * (ctrl: (p+1)*dim doubles) at t, by de Casteljau's algorithm (never the
 * power basis). Any finite t (outside [0, 1] extrapolates). out: dim
 * doubles. t == 0 and t == 1 give the end points exactly. Accuracy for t in
 * [0, 1]: absolute error <= about 2 p eps max|ctrl| (convex combinations).
 */
GEOM_API geom_status geom_curve_bezier_eval(int degree, size_t dim, const double *ctrl, double t,
                                   double *out);

/**
 * Point and derivatives 0..nderiv at t: derivative k is
 * p!/(p-k)! * sum_i Delta^k P_i B_{i,p-k}(t) (forward differences of the
 * control points, the hodographs), each evaluated by de Casteljau.
 * ders: (nderiv+1)*dim doubles; orders above p are zero.
 */
GEOM_API geom_status geom_curve_bezier_derivs(int degree, size_t dim, const double *ctrl, double t,
                                     int nderiv, double *ders);

/**
 * Split at t in [0, 1] (GEOM_ERR_DOMAIN otherwise) by de Casteljau: left
 * receives the control points of the piece over [0, t], right those over
 * [t, 1], each (p+1)*dim doubles; either may be NULL. The shared point is
 * bit-identical in both.
 */
GEOM_API geom_status geom_curve_bezier_split(int degree, size_t dim, const double *ctrl, double t,
                                    double *left, double *right);

/**
 * Degree elevation by `times` >= 0 (Farin: repeated single elevation,
 * Q_i = i/(p+1) P_{i-1} + (1 - i/(p+1)) P_i, convex combinations). out:
 * (p+times+1)*dim doubles. The curve is unchanged up to rounding.
 */
GEOM_API geom_status geom_curve_bezier_elevate(int degree, size_t dim, const double *ctrl, int times,
                                      double *out);

/** Box of the control polygon (contains the curve on [0, 1]). min, max: dim
 *  doubles each. */
GEOM_API geom_status geom_curve_bezier_bbox(int degree, size_t dim, const double *ctrl, double *min,
                                   double *max);

/**
 * Tight box of the curve over [0, 1]: per coordinate, the Bernstein
 * coefficients are subdivided around their extremes (branch and bound on
 * the convex hull property) until the gap between the lower bound (smallest
 * coefficient) and the best attained value (end coefficients, which lie on
 * the curve) is below 1e-15 times the coordinate's extent. The returned box
 * contains the curve and exceeds its exact extent by at most that gap.
 */
GEOM_API geom_status geom_curve_bezier_bbox_tight(int degree, size_t dim, const double *ctrl, double *min,
                                         double *max);

/* ---------------------------------------------- B-spline basis and knots */

/**
 * A2.1: the knot span index k (p <= k <= n-1, u_k < u_{k+1}) used to
 * evaluate at u in [u_p, u_n], by binary search: u_k <= u < u_{k+1} (right
 * limit), or u_k < u <= u_{k+1} with GEOM_CURVE_LEFT_LIMIT; the end rules
 * above apply. knots: n+degree+1 doubles. GEOM_ERR_DOMAIN if u is outside
 * the domain (unless GEOM_CURVE_WRAP), GEOM_ERR_INVALID_ARG if u is NaN/Inf.
 */
GEOM_API geom_status geom_curve_bspline_find_span(int degree, size_t n, const double *knots, double u,
                                         unsigned flags, size_t *span);

/**
 * A2.2: the degree+1 non-zero basis functions N_{k-p,p}(u) .. N_{k,p}(u) at u,
 * with span k from geom_curve_bspline_find_span(..., flags). The recurrence is
 * written so that a basis function equal to 1 (at a knot of multiplicity
 * >= p) comes out exactly 1. basis: degree+1 doubles; span may be NULL.
 * Accuracy: each value within a few ulp of 1 (they sum to 1).
 */
GEOM_API geom_status geom_curve_bspline_basis(int degree, size_t n, const double *knots, double u,
                                     unsigned flags, size_t *span, double *basis);

/**
 * A2.3: the non-zero basis functions and their derivatives 0..nderiv at u.
 * ders: (nderiv+1)*(degree+1) doubles, ders[k*(p+1) + j] = k-th derivative
 * of N_{span-p+j,p}(u); orders above p are zero. span may be NULL.
 */
GEOM_API geom_status geom_curve_bspline_basis_derivs(int degree, size_t n, const double *knots, double u,
                                            int nderiv, unsigned flags, size_t *span, double *ders);

/** Kinds of uniform knot vectors for geom_curve_bspline_uniform_knots(). */
typedef enum geom_knot_kind {
    /** p+1 copies of 0 and of 1, uniform interior knots: domain [0, 1]. */
    GEOM_KNOTS_CLAMPED = 0,
    /** u_i = (i - p)/(n - p), i = 0..n+p: uniform everywhere, domain [0, 1]. */
    GEOM_KNOTS_UNCLAMPED = 1,
    /** The same knots as GEOM_KNOTS_UNCLAMPED; with control points whose last
     *  p repeat the first p the curve is closed and C^{p-1} (periodic). */
    GEOM_KNOTS_PERIODIC = 2
} geom_knot_kind;

/** Uniform knot vector for n >= degree+1 >= 2 control points. knots:
 *  n+degree+1 doubles. */
GEOM_API geom_status geom_curve_bspline_uniform_knots(geom_knot_kind kind, int degree, size_t n,
                                             double *knots);

/* ------------------------------------------------------ NURBS / B-splines */

/**
 * Check a curve against the rules in the introduction: degree >= 1,
 * 1 <= dim <= GEOM_CURVE_MAX_DIM, n >= degree+1, nknots == n+degree+1 (the
 * number of knots the caller actually holds), non-NULL arrays, finite
 * nondecreasing knots, no knot value repeated more than degree+1 times, a
 * non-empty domain (u_p < u_n), finite points, finite weights > 0.
 * GEOM_OK, or GEOM_ERR_INVALID_ARG with the first violation in diag (e.g.
 * "knot 5 (0.2) is smaller than knot 4 (0.3)").
 */
GEOM_API geom_status geom_curve_nurbs_validate(const geom_nurbs_curve *c, size_t nknots, geom_diag *diag);

/** The parameter domain [u_p, u_n]. Either pointer may be NULL. */
GEOM_API geom_status geom_curve_nurbs_domain(const geom_nurbs_curve *c, double *u0, double *u1);

/**
 * A3.1 / A4.1: the point at u (rules at knots and ends above; flags
 * GEOM_CURVE_LEFT_LIMIT, GEOM_CURVE_WRAP). For a rational curve the point is
 * sum_i R_i P_i with R_i = N_i w_i / sum_j N_j w_j, so that an exact basis
 * value 1 gives the control point exactly. out: dim doubles.
 * Accuracy: absolute error a few ulp of max|P| over the span.
 * GEOM_ERR_INVALID_ARG (u NaN/Inf, bad sizes), GEOM_ERR_DOMAIN (u outside
 * the domain without GEOM_CURVE_WRAP).
 */
GEOM_API geom_status geom_curve_nurbs_eval(const geom_nurbs_curve *c, double u, unsigned flags, double *out);

/**
 * A3.2 / A4.2: the point and derivatives 0..nderiv (nderiv >= 0) at u. For a
 * rational curve the derivatives of A(u) = sum N_i w_i P_i and
 * w(u) = sum N_i w_i come from A2.3 and
 *   C^(k) = (A^(k) - sum_{i=1..k} binom(k,i) w^(i) C^(k-i)) / w.
 * ders: (nderiv+1)*dim doubles. Derivatives are one-sided as the rule at
 * knots says (use GEOM_CURVE_LEFT_LIMIT for the left derivative at a knot).
 * Accuracy: derivative k to about eps * max|P| / h^k, h the smallest knot
 * difference its basis functions divide by. GEOM_ERR_LIMIT if nderiv > 4096.
 */
GEOM_API geom_status geom_curve_nurbs_derivs(const geom_nurbs_curve *c, double u, int nderiv, unsigned flags,
                                    double *ders);

/**
 * Curvature at u: |C' x C''| / |C'|^3 (in any dimension via
 * sqrt(|C'|^2 |C''|^2 - (C'.C'')^2) / |C'|^3); for dim == 2 it is signed,
 * positive where the curve turns counter-clockwise. torsion (NULL allowed):
 * for dim == 3, (C' x C'') . C''' / |C' x C''|^2 (0 where the curvature is
 * 0); 0 for dim == 2; GEOM_ERR_INVALID_ARG if requested for dim 1 or 4.
 * GEOM_ERR_DEGENERATE if C'(u) == 0 (curvature undefined).
 */
GEOM_API geom_status geom_curve_nurbs_curvature(const geom_nurbs_curve *c, double u, unsigned flags,
                                       double *curvature, double *torsion);

/**
 * Build a closed periodic curve of degree p from m > p distinct control
 * points (and weights, or NULL): n = m + p control points (the first p
 * repeated at the end) and the uniform knots u_i = (i - p)/m, i = 0..m+2p,
 * so the domain is [0, 1] and the curve is C^{p-1} everywhere, including at
 * u = 0 == 1. Evaluate with GEOM_CURVE_WRAP to use any parameter.
 * knots: m+2p+1 doubles; points: (m+p)*dim; weights_out: m+p doubles (only
 * when weights != NULL). *out describes the result (borrowing the buffers).
 */
GEOM_API geom_status geom_curve_nurbs_periodic(int degree, size_t m, size_t dim, const double *points,
                                      const double *weights, double *knots, double *points_out,
                                      double *weights_out, geom_nurbs_curve *out);

/*
 * Knot operations. Each takes a valid curve c (checked with
 * geom_curve_nurbs_validate; GEOM_ERR_INVALID_ARG with the reason in diag
 * otherwise), writes the new knots, points and (only when c->weights is
 * non-NULL) weights into caller buffers, and sets *out to describe the new
 * curve (same degree unless stated, borrowing the buffers). Rational curves
 * are processed in homogeneous coordinates. The buffers must not overlap
 * c's arrays.
 */

/**
 * A5.1: insert the knot u `times` times (u in [u_p, u_n)). The new curve is
 * the same (to rounding: a few ulp of the control point magnitudes).
 * GEOM_ERR_DOMAIN if u is outside [u_p, u_n) or the multiplicity of u would
 * exceed the degree. knots: n+p+1+times doubles; points: (n+times)*dim;
 * weights: n+times.
 */
GEOM_API geom_status geom_curve_nurbs_insert_knot(const geom_nurbs_curve *c, double u, size_t times,
                                         double *knots, double *points, double *weights,
                                         geom_nurbs_curve *out, geom_diag *diag);

/**
 * A5.4: insert all knots of x (nx values, nondecreasing, in [u_p, u_n]) at
 * once. GEOM_ERR_DOMAIN if a value is outside the domain or a multiplicity
 * would exceed the degree (at the domain ends: if the end knot's total
 * multiplicity would exceed the degree). knots: n+p+1+nx; points:
 * (n+nx)*dim; weights: n+nx.
 */
GEOM_API geom_status geom_curve_nurbs_refine(const geom_nurbs_curve *c, const double *x, size_t nx,
                                    double *knots, double *points, double *weights,
                                    geom_nurbs_curve *out, geom_diag *diag);

/**
 * A5.8: remove the interior knot u (u_p < u < u_n, an existing knot) up to
 * `times` times, as long as each removal changes the curve by at most tol
 * (tol >= 0; for rational curves the book's conversion
 * tol * w_min / (1 + max|P|) is applied in homogeneous space). Each
 * accepted removal moves the curve by at most tol, so the result is within
 * removed*tol of c. *removed receives the number of removals made (0 is not
 * an error). knots: n+p+1; points: n*dim; weights: n (the input sizes; the
 * result is smaller by *removed). GEOM_ERR_DOMAIN if u is not an interior
 * knot.
 */
GEOM_API geom_status geom_curve_nurbs_remove_knot(const geom_nurbs_curve *c, double u, size_t times,
                                         double tol, double *knots, double *points, double *weights,
                                         geom_nurbs_curve *out, size_t *removed, geom_diag *diag);

/**
 * Sizes of the curve geom_curve_nurbs_elevate(c, times) produces: with s
 * distinct knot values strictly inside the domain, n + times*(s+1) points
 * and that + p + times + 1 knots. Either output may be NULL.
 * GEOM_ERR_LIMIT when degree + times exceeds 1000 (also refused by
 * geom_curve_nurbs_elevate: past degree ~1020 the binomial coefficients
 * overflow a double, which gave NaN control points).
 */
GEOM_API geom_status geom_curve_nurbs_elevate_bound(const geom_nurbs_curve *c, int times, size_t *n,
                                           size_t *nknots);

/**
 * A5.9: raise the degree by `times` >= 0 without changing the curve (to
 * rounding). The curve must be clamped at both ends (GEOM_ERR_DOMAIN
 * otherwise: use geom_curve_nurbs_clamp first); interior knots of any
 * multiplicity up to p+1 are allowed (each multiplicity grows by times).
 * Buffer sizes from geom_curve_nurbs_elevate_bound(); *out has degree
 * p + times.
 */
GEOM_API geom_status geom_curve_nurbs_elevate(const geom_nurbs_curve *c, int times, double *knots,
                                     double *points, double *weights, geom_nurbs_curve *out,
                                     geom_diag *diag);

/**
 * The same curve on the same domain with a clamped knot vector: the domain
 * ends are inserted (A5.4) until they have multiplicity p, then the control
 * points and knots outside the domain are dropped and the end knots
 * repeated p+1 times. A clamped curve is copied unchanged. Sizes: at most
 * n + 2p points (knots: that + p + 1); *out gives the actual n.
 */
GEOM_API geom_status geom_curve_nurbs_clamp(const geom_nurbs_curve *c, double *knots, double *points,
                                   double *weights, geom_nurbs_curve *out, geom_diag *diag);

/** Number of non-empty knot spans in the domain (= Bezier segments). */
GEOM_API geom_status geom_curve_nurbs_segments(const geom_nurbs_curve *c, size_t *nseg);

/**
 * A5.6: the Bezier segments of the curve, one per non-empty span, in order.
 * bezier_points: nseg*(p+1)*dim doubles (segment s at [s*(p+1)*dim ...]);
 * bezier_weights: nseg*(p+1) doubles, required iff c->weights != NULL;
 * breaks: NULL or nseg+1 doubles, the span end parameters (segment s
 * covers [breaks[s], breaks[s+1]] and maps it linearly onto [0, 1]).
 * Clamped curves use A5.6; others get each span's segment by blossoming
 * (the de Boor recurrence with the span's end knots as arguments).
 */
GEOM_API geom_status geom_curve_nurbs_decompose(const geom_nurbs_curve *c, double *bezier_points,
                                       double *bezier_weights, double *breaks, geom_diag *diag);

/* ------------------------------------------------------------------ conics */

/**
 * Number of control points and knots of an arc of the given sweep
 * (end - start, radians, 0 < |sweep| <= 2 pi): narcs = ceil(|sweep| / (pi/2))
 * pieces of at most 90 degrees, n = 2*narcs + 1, nknots = n + 3.
 * GEOM_ERR_DOMAIN if the sweep is 0 or above 2 pi (by more than 1e-12).
 */
GEOM_API geom_status geom_curve_nurbs_arc_bound(double start, double end, size_t *n, size_t *nknots);

/**
 * A7.1: exact rational quadratic arc of the ellipse
 *   E(theta) = center + cos(theta) * xaxis + sin(theta) * yaxis
 * for theta from start to end (end < start runs clockwise), split into
 * pieces of at most 90 degrees with middle weights cos(dtheta/2). xaxis and
 * yaxis are any two linearly independent vectors (their lengths are the
 * semi-axes when orthogonal); dim is 2, 3 or 4. Angles that are multiples of
 * pi/2 (as doubles) use exact cosines and sines. knots: nknots from
 * geom_curve_nurbs_arc_bound (domain [0, 1], double knots at i/narcs);
 * points: n*dim; weights: n. GEOM_ERR_DEGENERATE if the axes are parallel
 * or zero.
 */
GEOM_API geom_status geom_curve_nurbs_ellipse_arc(size_t dim, const double *center, const double *xaxis,
                                         const double *yaxis, double start, double end,
                                         double *knots, double *points, double *weights,
                                         geom_nurbs_curve *out, geom_diag *diag);

/**
 * Circular arc of radius r > 0: geom_curve_nurbs_ellipse_arc with axes
 * r*xaxis and r*yaxis, where xaxis, yaxis must be orthonormal (within
 * 1e-12; GEOM_ERR_INVALID_ARG otherwise).
 */
GEOM_API geom_status geom_curve_nurbs_arc(size_t dim, const double *center, const double *xaxis,
                                 const double *yaxis, double radius, double start, double end,
                                 double *knots, double *points, double *weights,
                                 geom_nurbs_curve *out, geom_diag *diag);

/**
 * Full circle as the classic 9-point rational quadratic (four 90-degree
 * arcs, The NURBS Book ch. 7): knots {0,0,0,1/4,1/4,1/2,1/2,3/4,3/4,1,1,1}, control points
 * the corners and edge midpoints of the square around the circle, weights
 * 1 and sqrt(2)/2. C(0) = C(1) = center + r*xaxis. knots: 12 doubles;
 * points: 9*dim; weights: 9. Axes as in geom_curve_nurbs_arc.
 */
GEOM_API geom_status geom_curve_nurbs_circle(size_t dim, const double *center, const double *xaxis,
                                    const double *yaxis, double radius, double *knots,
                                    double *points, double *weights, geom_nurbs_curve *out,
                                    geom_diag *diag);

/**
 * One conic arc as a rational quadratic Bezier curve (knots {0,0,0,1,1,1})
 * from p0 with tangent direction t0 to p2 with tangent direction t2. The
 * middle control point is where the tangent lines meet. Its weight is
 * `weight` when point == NULL, else computed so the curve passes through
 * `point` (The NURBS Book A7.2; for the shoulder point, the curve point at
 * u = 1/2, this gives w = s/(1-s) with s the ratio |S - M| / |P1 - M|,
 * M = (p0+p2)/2). w < 1 ellipse, == 1 parabola, > 1 hyperbola.
 * GEOM_ERR_DEGENERATE if the tangent lines are parallel or do not meet
 * (split such an arc in two), GEOM_ERR_DOMAIN if the weight is not > 0 or
 * the point cannot lie on such an arc. knots: 6 doubles; points: 3*dim;
 * weights: 3 (w0 = w2 = 1).
 */
GEOM_API geom_status geom_curve_nurbs_conic(size_t dim, const double *p0, const double *t0, const double *p2,
                                   const double *t2, const double *point, double weight,
                                   double *knots, double *points, double *weights,
                                   geom_nurbs_curve *out, geom_diag *diag);

/* ------------------------------------------------------ geometric queries */

/**
 * Arc length of c over [u0, u1] (u_p <= u0 <= u1 <= u_n): adaptive
 * Gauss-Legendre quadrature of |C'(u)| on every non-empty knot span in the
 * interval (the speed is smooth inside a span). Each interval is integrated
 * with 8 points, then on its two halves; the halves are accepted when they
 * differ from the whole by less than the interval's share of rel_tol times
 * the length (or by less than the rounding noise of the sums), otherwise
 * they are refined, up to 50 levels and 2^21 evaluations in all.
 * rel_tol: relative tolerance, 0 means 1e-13 (values below 1e-15 are
 * raised to it). report (NULL allowed): max_error = the sum of the accepted
 * |whole - halves| differences, an estimate of the absolute error
 * (pessimistic: the returned value is the more accurate halves);
 * mean_error = max_error / number of intervals; method =
 * GEOM_ERROR_ESTIMATE; evaluations = derivative evaluations.
 * GEOM_ERR_LIMIT if a limit was reached before the tolerance (*length and
 * the report are then still filled with the best estimate). Accuracy: for
 * curves far from the origin the speed is only known to about
 * eps * |offset| / span, which bounds the reachable tolerance.
 */
GEOM_API geom_status geom_curve_nurbs_arc_length(const geom_nurbs_curve *c, double u0, double u1,
                                        double rel_tol, double *length, geom_error_report *report,
                                        geom_diag *diag);

/**
 * Global closest point on c to q (dim doubles). Every span's Bezier
 * segment is subdivided (branch and bound: a piece is dropped when the
 * box of its control points, which contains it, is farther than the best
 * distance found), and the surviving small pieces are finished with Newton
 * steps on (C(u) - q) . C'(u) = 0 safeguarded by bisection. A piece whose
 * Bernstein sign test shows (C - q) . C' with no sign change is settled by
 * its end points, one change from - to + by Newton, and a piece on which
 * the squared distance cannot vary by more than a relative 1e-15 by its end
 * points; others are split (up to 60 levels). Outputs (each NULL allowed):
 * u, point (dim doubles), distance. When several points are equally close,
 * one of them is returned. Accuracy: the distance is the global minimum to
 * about 1e-14 relative (the parameter and point to about the square root of
 * that where the minimum is flat). Degrees above about 300 overflow the
 * binomials of the sign test.
 */
GEOM_API geom_status geom_curve_nurbs_closest_point(const geom_nurbs_curve *c, const double *q, double *u,
                                           double *point, double *distance, geom_diag *diag);

/** Options for geom_curve_nurbs_polyline; valid when zero-initialised. */
typedef struct geom_curve_polyline_options {
    /** Chordal tolerance (absolute). 0 means 1e-3 times the diagonal of the
     *  control points' box. */
    double tolerance;
    /** GEOM_ERROR_BOUND (0 also means this): the deviation of a piece from
     *  its chord is bounded by the largest distance of its Bezier control
     *  points from the chord segment (convex hull property), so the
     *  polyline is within tolerance of the curve (Hausdorff distance).
     *  GEOM_ERROR_SAMPLED: the deviation is measured at 7 interior sample
     *  points of each piece (cheaper subdivision, not a guarantee). */
    int method;
    /** Maximum number of vertices; 0 means 1 << 20. GEOM_ERR_LIMIT when
     *  the tolerance needs more. */
    size_t max_points;
} geom_curve_polyline_options;

/**
 * Adaptive polyline of c over its domain to a chordal tolerance. Every
 * non-empty span's Bezier segment is subdivided at parameter midpoints
 * until each piece deviates from its chord by at most the tolerance,
 * measured as options->method says. Vertices are curve points (exact
 * control points at the span ends). params (NULL allowed) and points
 * (NULL allowed) receive *count parameters and *count*dim coordinates when
 * *count <= capacity; with points == NULL only *count is computed.
 * GEOM_ERR_LIMIT if capacity (when points != NULL) or max_points is too
 * small (*count is then the number needed, or 0 when max_points was hit).
 * report (NULL allowed): max_error / mean_error over the pieces of the
 * measured deviation (bound or sampled), method, evaluations = de Casteljau
 * subdivisions plus sample evaluations.
 * Control points anywhere in the range of double work (distances are
 * computed with scaling, never by squaring raw coordinates): the default
 * tolerance and the reported errors are finite for control points up to
 * about 1e308. GEOM_ERR_DOMAIN when a deviation cannot be represented (a
 * rational curve whose points overflow), never a silent 0.
 */
GEOM_API geom_status geom_curve_nurbs_polyline(const geom_nurbs_curve *c,
                                      const geom_curve_polyline_options *options, double *params,
                                      double *points, size_t capacity, size_t *count,
                                      geom_error_report *report, geom_diag *diag);

/**
 * The number of vertices geom_curve_nurbs_polyline returns for c and
 * options (tolerance and method; max_points is ignored), estimated before
 * the work from each non-empty span's Bezier control points, in
 * O(spans * degree^2) without subdividing: a span whose Bezier control
 * polygon has second differences of norm at most M (Euclidean points) is
 * within the tolerance once split into 2^k equal pieces with
 * 4^-k K M <= tolerance, K = floor(p/2) ceil(p/2) / 2 (de Casteljau halving
 * scales the second differences by 1/4; the control points' distance to
 * the chord, which both methods stay below, is at most K times their
 * largest norm). *count (a double: it may exceed SIZE_MAX) is the sum over
 * spans of 1 + 2^k, k capped at the polyline's depth limit of 50.
 *
 * Accuracy: for a polynomial curve (weights NULL) *count is an upper bound
 * on the polyline's count (with an allowance of a few ulp of the
 * coordinates for rounding: a tolerance below that gives the depth
 * limit) and *is_bound is 1. The adaptive subdivision stops earlier where
 * the curve is flatter: on 1,800 random curves in 2-4 dimensions (degree
 * 1-5, tolerances 1e-6..1e-1 and the default) the bound was 1.0-5.4x the
 * count (median 2.1, 99th percentile 4.8); degree 1 gives 2 per span
 * (each span's first point is counted, as a jump would repeat it). It is
 * loose where control points are (nearly) collinear but
 * unevenly spaced, as always in 1D (second differences along a line do not
 * vanish; up to 2^14x was seen). For a rational curve the weights' spread per span (max/min) scales M:
 * an estimate, not a bound (*is_bound 0): for the circle of four
 * quadratic arcs 1.0-1.2x the count, for 400 random rational curves
 * 1.1-17.5x (never below the count there, but nothing guarantees it).
 * is_bound may be NULL.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (an invalid curve, as
 * geom_curve_nurbs_validate says, bad options, NULL count);
 * GEOM_ERR_DOMAIN (control points whose differences overflow to NaN);
 * GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_curve_nurbs_polyline_estimate(const geom_nurbs_curve *c,
                                                        const geom_curve_polyline_options *options,
                                                        double *count, int *is_bound,
                                                        geom_diag *diag);

/* ------------------------------------------------------------ batches */

/**
 * geom_curve_bspline_basis_derivs at m parameters u (m doubles) in one
 * call: ders receives m rows of (nderiv+1)*(degree+1) doubles (row i at
 * i*(nderiv+1)*(degree+1), laid out as the single function's), spans (m
 * values, NULL allowed) each row's span (SIZE_MAX where it failed); a
 * failing row is NaN with its status in status (m int32 values, NULL
 * allowed), counted in *n_failed (NULL allowed). Returns GEOM_OK, or
 * GEOM_ERR_INVALID_ARG for NULL knots/u/ders or a negative degree/nderiv
 * with m > 0.
 */
GEOM_API geom_status geom_curve_bspline_basis_many(int degree, size_t n, const double *knots, size_t m,
                                                   const double *u, int nderiv, unsigned flags,
                                                   size_t *spans, double *ders, int32_t *status,
                                                   size_t *n_failed);

/**
 * geom_curve_nurbs_eval at n parameters u (n doubles) in one call (for
 * bindings; same results): out receives n*dim doubles, row by row; a row
 * whose evaluation fails is NaN, its status (n int32 values, NULL allowed)
 * the geom_status, counted in *n_failed (NULL allowed). Returns GEOM_OK, or
 * GEOM_ERR_INVALID_ARG for NULL c/u/out or a bad dim with n > 0.
 */
GEOM_API geom_status geom_curve_nurbs_eval_many(const geom_nurbs_curve *c, size_t n, const double *u,
                                                unsigned flags, double *out, int32_t *status,
                                                size_t *n_failed);
/**
 * Euclidean distance from point q to the segment [a, b] (dim doubles each,
 * 1 <= dim <= GEOM_CURVE_MAX_DIM), computed with scaling so that it is
 * accurate for coordinates anywhere in the range of double (no overflow in
 * squares or differences below the result itself). A zero-length segment
 * gives the distance to a. NaN if any input is NaN; +inf only when the true
 * distance exceeds DBL_MAX.
 */
GEOM_API double geom_curve_segment_distance(size_t dim, const double *a, const double *b,
                                            const double *q);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_CURVE_H */
