/*
 * libgeom surface: Bezier, B-spline and NURBS tensor-product surfaces:
 * evaluation, partial derivatives of any order, normals everywhere
 * (including degenerate points), exact constructions (bilinear, ruled,
 * extrusion, revolution, sphere, cylinder, cone, torus), the Bezier patch
 * file format (.bpt), and crack-free tessellation to a geom_mesh.
 *
 * References: L. Piegl and W. Tiller, The NURBS Book, 2nd ed., Springer 1997
 * (A3.5/A3.6 surface points and derivatives, A4.3/A4.4 their rational
 * forms, A8.1 surfaces of revolution, section 8.5 the sphere and torus);
 * D. Filip, R. Magedson and R. Markot, "Surface algorithms using bounds on
 * derivatives", CAGD 3(4), 1986 (the chordal error of a parametric grid);
 * M. Newell's teapot (the .bpt data).
 *
 * Conventions:
 *  - Surfaces live in 3D. Control point (i, j) -- i along u, j along v --
 *    is points[3*(i*nv + j) .. +3]; its weight (rational surfaces) is
 *    weights[i*nv + j], finite and > 0. Points are Euclidean, NOT
 *    multiplied by the weight; internally the algorithms work on the
 *    homogeneous points (w P, w).
 *  - Knot vectors follow geom/curve.h in each direction: degree p >= 1,
 *    n >= p+1 control points, n+p+1 nondecreasing knots, no value repeated
 *    more than p+1 times, u_p < u_n. The domain is [u_p, u_n] x [v_q, v_m].
 *    A Bezier patch of degrees (p, q) is the special case with knots
 *    {0 (p+1 times), 1 (p+1 times)} (geom_surface_bezier()).
 *  - Rule at knots, per direction, as for curves: right limits inside the
 *    domain unless GEOM_SURFACE_U_LEFT / GEOM_SURFACE_V_LEFT ask for the
 *    left limit; at the domain ends the only side there is. A clamped
 *    surface gives its corner control points exactly (bit for bit) at the
 *    domain corners, and a boundary row of control points that are all
 *    equal (a collapsed edge, a pole) evaluates to that point there up to
 *    rounding.
 *  - Every function returns geom_status: GEOM_OK, GEOM_ERR_INVALID_ARG for
 *    NULL where not allowed, a bad size or a NaN/Inf number, GEOM_ERR_DOMAIN
 *    for a finite argument outside the domain, others where listed. On
 *    failure the outputs are unspecified unless stated. Functions taking a
 *    `geom_diag *` (NULL allowed) put a one-line reason there.
 *  - The evaluation functions check only the cheap things (pointers, sizes,
 *    the parameters); call geom_surface_validate() once on untrusted input.
 *  - Nothing prints or keeps global state; every function is reentrant.
 *    Scratch memory grows with the degrees: up to about degree 25 it lives
 *    on the stack, above that evaluation allocates with malloc and can
 *    return GEOM_ERR_NOMEM.
 */
#ifndef GEOM_SURFACE_H
#define GEOM_SURFACE_H

#include "geom/core.h"
#include "geom/curve.h"
#include "geom/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ types */

/**
 * A B-spline (weights == NULL) or NURBS tensor-product surface; all arrays
 * are borrowed:
 *   knots_u: nu + degree_u + 1 doubles;  knots_v: nv + degree_v + 1;
 *   points:  3*nu*nv doubles, point (i, j) at 3*(i*nv + j);
 *   weights: NULL, or nu*nv doubles > 0, weight (i, j) at i*nv + j.
 */
typedef struct geom_nurbs_surface {
    int degree_u, degree_v;
    size_t nu, nv;
    const double *knots_u;
    const double *knots_v;
    const double *points;
    const double *weights;
} geom_nurbs_surface;

/** Evaluation flags (bitwise or); 0 means right limits in both directions. */
enum {
    GEOM_SURFACE_U_LEFT = 1u << 0, /**< left limit in u at an interior knot */
    GEOM_SURFACE_V_LEFT = 1u << 1  /**< left limit in v at an interior knot */
};

/* ------------------------------------------------------------ evaluation */

/**
 * Check s against the rules above: degrees >= 1, counts >= degree+1,
 * non-NULL arrays, finite nondecreasing knots in each direction with no
 * value repeated more than degree+1 times and a non-empty domain, finite
 * points, finite weights > 0. GEOM_OK or GEOM_ERR_INVALID_ARG with the first
 * violation in diag (e.g. "knots_v: knot 3 (0.2) is smaller than knot 2
 * (0.5)", "weights: weight (2, 1) is -1, not > 0").
 */
GEOM_API geom_status geom_surface_validate(const geom_nurbs_surface *s, geom_diag *diag);

/** The domain as 4 doubles: u0, u1, v0, v1. */
GEOM_API geom_status geom_surface_domain(const geom_nurbs_surface *s, double domain[4]);

/**
 * A3.5 / A4.3: the point S(u, v) (3 doubles) with the rule at knots above.
 * For a rational surface S = sum R_ij P_ij with R_ij = N_i M_j w_ij / W, so
 * an exact basis value 1 in both directions gives the control point exactly.
 * Accuracy: absolute error a few ulp of max |P| over the span's control
 * points. GEOM_ERR_DOMAIN for (u, v) outside the domain.
 */
GEOM_API geom_status geom_surface_eval(const geom_nurbs_surface *s, double u, double v, unsigned flags,
                              double out[3]);

/**
 * A3.6 / A4.4: all partial derivatives S^(k,l) = d^(k+l) S / du^k dv^l with
 * k + l <= d (d >= 0) at (u, v). ders: 3*(d+1)*(d+1) doubles, S^(k,l) at
 * 3*(k*(d+1) + l); entries with k + l > d are set to zero; S^(0,0) is
 * bit-identical to geom_surface_eval. For rational surfaces
 *   S^(k,l) = (A^(k,l) - sum_{j=1..l} C(l,j) w^(0,j) S^(k,l-j)
 *              - sum_{i=1..k} C(k,i) w^(i,0) S^(k-i,l)
 *              - sum_{i=1..k} C(k,i) sum_{j=1..l} C(l,j) w^(i,j) S^(k-i,l-j)) / w.
 * The derivatives are computed from control points relative to one of the
 * span's control points, so a surface far from the origin loses no accuracy
 * to its offset. Derivatives are one-sided as the flags say.
 * Accuracy: order (k, l) to about eps * (extent of the span's control
 * points) / (hu^k hv^l), h the knot differences the basis divides by.
 * GEOM_ERR_LIMIT if d > 64.
 */
GEOM_API geom_status geom_surface_derivs(const geom_nurbs_surface *s, double u, double v, int d,
                                unsigned flags, double *ders);

/** How a normal was obtained (geom_surface_normal's *how). */
enum {
    GEOM_SURFACE_NORMAL_REGULAR = 0, /**< S_u x S_v at the point */
    GEOM_SURFACE_NORMAL_LIMIT = 1,   /**< the limit of S_u x S_v approaching the point */
    GEOM_SURFACE_NORMAL_NONE = 2     /**< no direction found: the surface is a point there */
};

/**
 * Unit normal n (3 doubles) in the direction of S_u x S_v, defined
 * everywhere the surface is not locally a single point.
 *
 * At a regular point it is S_u x S_v normalised. At a degenerate point
 * (S_u or S_v zero, or parallel -- the poles of a sphere, the collapsed edge
 * of a Bezier patch, a cone's apex) it is the limit of the normal along the
 * ray (u + t a, v + t b), t -> 0+, entering the domain: (a, b) is (0, +-1)
 * when S_u vanishes (the collapsed direction), (+-1, 0) when S_v does, and
 * diagonal otherwise, each sign pointing into the knot span that is
 * evaluated (the side the flags select) when the point lies at an end of
 * it, else toward the middle of the domain.
 * With S_u(t) x S_v(t) = sum_m c_m t^m (Taylor expansion from the higher
 * partial derivatives S^(k,l), k + l <= 9), the normal is c_m / |c_m| for
 * the first m whose c_m exceeds the rounding noise of the derivatives. On a
 * smooth surface (the poles of a sphere, the lid of the teapot) this is the
 * tangent plane's normal; at a cone's apex it is the normal along the
 * ruling through (u, v).
 *
 * A vector counts as zero when it is below its rounding noise: 64 (p+q) eps
 * times the first derivatives' sums of magnitudes at the point (basis
 * derivatives times weights times the control points' distances from the
 * span's first one, over the weight function), derivatives being scaled by
 * the span widths (higher orders: times 4 per order); S_u x S_v counts as
 * regular when it exceeds 1000 (noise(S_u) |S_v| + noise(S_v) |S_u|).
 *
 * how (NULL allowed) receives GEOM_SURFACE_NORMAL_REGULAR or _LIMIT, or
 * _NONE when every coefficient vanishes: then n = (0, 0, 0) and the status
 * is GEOM_ERR_DEGENERATE (never NaN). flags as for geom_surface_eval.
 */
GEOM_API geom_status geom_surface_normal(const geom_nurbs_surface *s, double u, double v, unsigned flags,
                                double n[3], int *how);

/* ----------------------------------------------------------- construction */
/*
 * Constructors write into caller buffers whose sizes are stated (or given by
 * a *_bound function) and set *out to describe the result (borrowing the
 * buffers). Sizes: knots_u nu+pu+1, knots_v nv+pv+1, points 3*nu*nv,
 * weights nu*nv (rational results only).
 */

/**
 * Knots {0 x (p+1), 1 x (p+1)} of a Bezier patch of degree p >= 1 in one
 * direction (knots: 2p+2 doubles).
 */
GEOM_API geom_status geom_surface_bezier_knots(int degree, double *knots);

/**
 * A Bezier patch of degrees (pu, pv) >= 1 over [0,1]^2 from (pu+1)(pv+1)
 * control points (layout as above; weights NULL or (pu+1)(pv+1) values):
 * fills knots_u (2pu+2) and knots_v (2pv+2) and *out, which borrows
 * points, weights and the knots.
 */
GEOM_API geom_status geom_surface_bezier(int degree_u, int degree_v, const double *points,
                                const double *weights, double *knots_u, double *knots_v,
                                geom_nurbs_surface *out);

/**
 * Bilinear patch S(u,v) = (1-u)(1-v) p00 + u(1-v) p10 + (1-u)v p01 + uv p11
 * over [0,1]^2 (degree 1 x 1, 2 x 2 points). knots_u, knots_v: 4 doubles;
 * points: 12.
 */
GEOM_API geom_status geom_surface_bilinear(const double p00[3], const double p10[3], const double p01[3],
                                  const double p11[3], double *knots_u, double *knots_v,
                                  double *points, geom_nurbs_surface *out);

/**
 * Extrusion (general cylinder) S(u, v) = C(u) + v d, v in [0, 1]: c is a
 * valid curve of dimension 2 (z = 0) or 3, d 3 doubles, not zero
 * (GEOM_ERR_DEGENERATE). Degrees (p, 1), nu = c->n, nv = 2, knots_u are c's
 * knots, knots_v {0,0,1,1}. Rational when c is.
 */
GEOM_API geom_status geom_surface_extrude(const geom_nurbs_curve *c, const double d[3], double *knots_u,
                                 double *knots_v, double *points, double *weights,
                                 geom_nurbs_surface *out, geom_diag *diag);

/**
 * Sizes of the ruled surface of c0 and c1 (geom_surface_ruled): nu control
 * points along u and nknots_u knots (either pointer may be NULL). The
 * surface has degree max(p0, p1) in u, 1 in v, nv = 2.
 */
GEOM_API geom_status geom_surface_ruled_bound(const geom_nurbs_curve *c0, const geom_nurbs_curve *c1,
                                     size_t *nu, size_t *nknots_u);

/**
 * Ruled surface S(u, v) = (1-v) C0(u) + v C1(u) (The NURBS Book section
 * 10.3; for rational curves the interpolation is in homogeneous space:
 * S = ((1-v) w0 C0 + v w1 C1) / ((1-v) w0 + v w1) with w0(u), w1(u) the
 * curves' weight functions). The curves (dimension 2 or 3, valid) are first made compatible:
 * clamped (geom_curve_nurbs_clamp), their domains mapped linearly onto
 * [0, 1], the lower degree raised (geom_curve_nurbs_elevate) and each knot
 * vector refined with the other's knots (geom_curve_nurbs_refine); each
 * curve is unchanged by this up to rounding. The result is rational when
 * either curve is (weights NULL allowed otherwise). u runs along the curves
 * (normalised to [0, 1]), v from c0 to c1. Buffer sizes from
 * geom_surface_ruled_bound (knots_v: 4). May allocate scratch memory:
 * GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_surface_ruled(const geom_nurbs_curve *c0, const geom_nurbs_curve *c1,
                               double *knots_u, double *knots_v, double *points, double *weights,
                               geom_nurbs_surface *out, geom_diag *diag);

/**
 * Sizes of a surface of revolution of a profile with n control points
 * through `angle` radians (0 < |angle| <= 2 pi): nu = 2*narcs + 1 points
 * around the axis (narcs = number of arcs of at most 90 degrees,
 * geom_curve_nurbs_arc_bound) and nknots_u = nu + 3; nv = n.
 */
GEOM_API geom_status geom_surface_revolve_bound(double angle, size_t *nu, size_t *nknots_u);

/**
 * A8.1: exact surface of revolution of the profile curve c (dimension 2,
 * taken as the (x, z) half-plane coordinates: radius and height; or 3, a
 * 3D curve) about the axis through `origin` with direction `axis` (3
 * doubles each, axis not zero), sweeping `angle` radians counter-clockwise
 * about the axis (right-hand rule; negative angles turn clockwise).
 * u runs around the axis over [0, 1] (rational quadratic arcs, The NURBS
 * Book A7.1; a full turn is the 9-point circle with exact weights 1 and
 * sqrt(2)/2 and identical first and last rows), v along the profile
 * (c's knots). Control point (i, j) is the profile point j turned by the
 * i-th arc point: O_j + r_j (cos X_j + sin Y_j) with O_j its projection on
 * the axis; weights w_i^arc * w_j. Profile points on the axis give a
 * collapsed row (a pole) that equals the profile point exactly. With a 2D
 * profile the half-plane is spanned by `xaxis` (radius) and `axis`
 * (height), both taken from the arguments: xaxis must be non-zero and
 * orthogonal to axis (within 1e-12; NULL: a fixed perpendicular of axis).
 * For a 3D profile xaxis is ignored. Su x Sv points away from the axis when
 * the profile runs in the +axis direction on the positive side.
 * knots_u: nknots_u from geom_surface_revolve_bound; knots_v: c->n +
 * c->degree + 1; points: 3*nu*c->n; weights: nu*c->n (always rational).
 * GEOM_ERR_DEGENERATE for a zero axis, GEOM_ERR_DOMAIN for a bad angle.
 */
GEOM_API geom_status geom_surface_revolve(const geom_nurbs_curve *c, const double origin[3],
                                 const double axis[3], const double *xaxis, double angle,
                                 double *knots_u, double *knots_v, double *points, double *weights,
                                 geom_nurbs_surface *out, geom_diag *diag);

/**
 * A frame for the analytic constructors: center (3 doubles), z axis (the
 * axis of symmetry) and x axis (where u = 0), both unit and orthogonal
 * within 1e-12 (GEOM_ERR_INVALID_ARG otherwise). NULL means the world frame
 * at the origin.
 */
typedef struct geom_surface_frame {
    double center[3];
    double zaxis[3];
    double xaxis[3];
} geom_surface_frame;

/**
 * Exact NURBS sphere of radius r > 0 (The NURBS Book 8.5): the 5-point
 * rational semicircle from the south pole (-z) to the north pole (+z),
 * revolved through 2 pi. Degrees (2, 2), nu = 9, nv = 5, knots_u
 * {0,0,0,1/4,1/4,1/2,1/2,3/4,3/4,1,1,1} (12 doubles), knots_v
 * {0,0,0,1/2,1/2,1,1,1} (8), points 135 doubles, weights 45. u is the
 * longitude, v the latitude; Su x Sv points outward; the rows j = 0 and
 * j = 4 are the poles (exactly center -+ r z), rows i = 0 and i = 8 are
 * identical (the seam).
 */
GEOM_API geom_status geom_surface_sphere(const geom_surface_frame *frame, double radius, double *knots_u,
                                double *knots_v, double *points, double *weights,
                                geom_nurbs_surface *out);

/**
 * Exact circular cylinder of radius r > 0 from the frame's center along +z
 * to height h != 0: degrees (2, 1), nu = 9, nv = 2; knots_u as the sphere
 * (12), knots_v {0,0,1,1} (4), points 54, weights 18. Su x Sv points
 * outward for h > 0.
 */
GEOM_API geom_status geom_surface_cylinder(const geom_surface_frame *frame, double radius, double height,
                                  double *knots_u, double *knots_v, double *points,
                                  double *weights, geom_nurbs_surface *out);

/**
 * Exact circular cone (frustum) with radius r0 at the center (v = 0) and r1
 * at height h (v = 1), r0, r1 >= 0 not both 0, h != 0: degrees (2, 1),
 * sizes as the cylinder. A zero radius gives an apex (a collapsed row),
 * where geom_surface_normal returns the normal along each ruling.
 */
GEOM_API geom_status geom_surface_cone(const geom_surface_frame *frame, double r0, double r1,
                              double height, double *knots_u, double *knots_v, double *points,
                              double *weights, geom_nurbs_surface *out);

/**
 * Exact torus with major radius R (center to tube center) and minor radius
 * r, 0 < r, 0 < R (R <= r gives a self-intersecting spindle torus; allowed):
 * the 9-point circle of radius r in the (x, z) half-plane around (R, 0)
 * revolved through 2 pi. Degrees (2, 2), nu = nv = 9, knots_u and knots_v as
 * the sphere's knots_u (12 each), points 243, weights 81. u runs around the
 * axis, v around the tube starting on the outer equator; Su x Sv points
 * outward; rows i = 0, 8 and columns j = 0, 8 are the identical seams.
 */
GEOM_API geom_status geom_surface_torus(const geom_surface_frame *frame, double major_radius,
                               double minor_radius, double *knots_u, double *knots_v,
                               double *points, double *weights, geom_nurbs_surface *out);

/* ------------------------------------------------------------ surface sets */

/**
 * An owning list of surfaces (each stored in one block: knots, points,
 * weights), as the file readers produce. Entries are read through borrowed
 * views valid until the set changes or is destroyed.
 */
typedef struct geom_surface_set geom_surface_set;

/** A new empty set (alloc NULL: libc). NULL when out of memory. */
GEOM_API geom_surface_set *geom_surface_set_create(const geom_allocator *alloc);
/** Free the set and its surfaces. NULL is a no-op. */
GEOM_API void geom_surface_set_destroy(geom_surface_set *set);
/** Number of surfaces. */
GEOM_API size_t geom_surface_set_count(const geom_surface_set *set);
/**
 * Append a deep copy of s (not validated here) with an optional name (NULL
 * or up to 63 bytes kept). GEOM_ERR_INVALID_ARG for NULL set/s or missing
 * arrays, GEOM_ERR_NOMEM, GEOM_ERR_LIMIT (size overflow).
 */
GEOM_API geom_status geom_surface_set_add(geom_surface_set *set, const geom_nurbs_surface *s,
                                 const char *name);
/** The views of all surfaces: count entries (NULL when empty). */
GEOM_API const geom_nurbs_surface *geom_surface_set_data(const geom_surface_set *set);
/** The name of surface i ("" when unnamed; NULL if i is out of range). */
GEOM_API const char *geom_surface_set_name(const geom_surface_set *set, size_t i);

/* -------------------------------------------------------------- .bpt files */

/**
 * Read Bezier patches in the classic text format of Newell's teapot data:
 *   line 1: the patch count N;
 *   N lines of 16 one-based point indices of a bicubic patch, four rows of
 *     four: item 4*r + c (0-based) is control point (i = c, j = r), i.e.
 *     the rows run along u (with this reading Newell's teapot patches have
 *     Su x Sv pointing outward);
 *   the point count M;
 *   M lines of x, y, z.
 * Numbers are separated by commas and/or blanks; blank lines and lines
 * starting with '#' are skipped. Each patch becomes a bicubic Bezier surface
 * (knots {0,0,0,0,1,1,1,1}) appended to *out (a new set; free it with
 * geom_surface_set_destroy; NULL on error). Errors name source:line:column:
 * GEOM_ERR_PARSE (malformed number, wrong count on a line, an index out of
 * 1..M, missing or extra lines), GEOM_ERR_LIMIT (counts above 2^24),
 * GEOM_ERR_NOMEM. data need not be NUL-terminated (size bytes);
 * source_name (NULL: "<memory>") names it in diagnostics.
 */
GEOM_API geom_status geom_surface_read_bpt_memory(const void *data, size_t size, const char *source_name,
                                         const geom_allocator *alloc, geom_surface_set **out,
                                         geom_diag *diag);

/** geom_surface_read_bpt_memory on the contents of the file at path
 *  (GEOM_ERR_IO with the system's reason when it cannot be read). */
GEOM_API geom_status geom_surface_read_bpt(const char *path, const geom_allocator *alloc,
                                  geom_surface_set **out, geom_diag *diag);

/* ------------------------------------------------------------ tessellation */

/** Tessellation modes. */
typedef enum geom_surface_tess_mode {
    /** Default: per cell (knot span, or whole Bezier patch) a grid sized to
     *  the chordal tolerance, verified and refined (see below). */
    GEOM_SURFACE_TESS_ADAPTIVE = 0,
    /** grid_u x grid_v quads per cell (or per surface, see per_surface). */
    GEOM_SURFACE_TESS_UNIFORM = 1
} geom_surface_tess_mode;

/** Attribute bits for geom_surface_tess_options.attributes. */
#define GEOM_SURFACE_ATTR_NORMAL 1u  /**< CORNER "normal" (3): analytic unit normals */
#define GEOM_SURFACE_ATTR_UV 2u      /**< CORNER "uv" (2): surface parameters */
#define GEOM_SURFACE_ATTR_TANGENT 4u /**< CORNER "tangent" (4): unit dP/du, w = +-1 */
#define GEOM_SURFACE_ATTR_SOURCE 8u  /**< FACE "surface" (1): index of the face's surface */

/** Options; valid when zero-initialised (0 means the documented default). */
typedef struct geom_surface_tess_options {
    geom_surface_tess_mode mode;
    /** Adaptive mode: chordal tolerance (absolute, > 0). 0 means 1e-3 times
     *  the diagonal of the box of all control points. */
    double tolerance;
    /** Adaptive mode: if > 0, also refine until the analytic normals at the
     *  three corners of every triangle are within this angle (degrees) of
     *  each other. */
    double angle_degrees;
    /** Uniform mode: quads per cell along u and v (0 means 8; at most
     *  65536). */
    int grid_u, grid_v;
    /** Uniform mode: nonzero makes the grid_u x grid_v grid span each whole
     *  surface instead of each knot span (grid lines then ignore the knots). */
    int per_surface;
    /** OR of GEOM_SURFACE_ATTR_* bits: the channels to make (positions are
     *  always made). */
    unsigned attributes;
    /** Nonzero: "uv" holds the parameters normalised to [0,1]^2 over each
     *  surface's domain instead of the parameters themselves. */
    int uv_normalized;
    /** Nonzero: do not weld boundaries of different surfaces (or the seams
     *  of one surface); each surface is then its own component. */
    int no_weld;
    /** Nonzero: keep every surface's own orientation even where a welded
     *  neighbour disagrees (by default the surfaces of a welded group are
     *  flipped to agree with its first surface). */
    int keep_orientation;
    /** Barycentric subdivisions per triangle side for the error check
     *  (0 means 4: 12 points per triangle besides its corners). */
    int check_subdivisions;
    /** Largest number of triangles (0 means 2^24): GEOM_ERR_LIMIT beyond. */
    size_t max_triangles;
    /** Allocator for the mesh's temporary memory; NULL = libc. */
    const geom_allocator *alloc;
    /** Normal welding (with GEOM_SURFACE_ATTR_NORMAL): the corner normals of
     *  one vertex (patches meeting at a seam or a corner) that are within
     *  this angle (degrees) of each other become one normal value, the first
     *  patch's, so a renderer does not split the vertex for the rounding
     *  difference of two evaluations. Normals further apart (creases, poles
     *  approached from different patches) stay apart. 0 means
     *  GEOM_SURFACE_NORMAL_WELD_DEFAULT; negative: no welding (every corner
     *  keeps its own patch's analytic normal). */
    double normal_weld_degrees;
    /** Progress (NULL: none): called on the calling thread after each cell
     *  of each pass with the fraction (0..1] of that pass's cells done. A
     *  pass is a triangulation and error check of every cell; adaptive
     *  tessellation runs one per refinement (the fraction then restarts
     *  from 0) and a last one that makes the output. */
    void (*progress)(void *user, double fraction);
    void *progress_user; /**< passed to progress */
} geom_surface_tess_options;

/** Default angle (degrees) under which the corner normals of one vertex are
 *  welded by geom_surface_tessellate: a welded normal is then within this
 *  angle of the patch's analytic normal. */
#define GEOM_SURFACE_NORMAL_WELD_DEFAULT 0.01

/** What a tessellation made, besides the error report. */
typedef struct geom_surface_tess_stats {
    size_t cells;             /**< knot-span (or patch) cells tessellated */
    size_t triangles;         /**< faces of the mesh */
    size_t vertices;          /**< vertices of the mesh */
    size_t welded_edges;      /**< cell edges shared with another surface (or a seam) */
    size_t collapsed_edges;   /**< cell edges that are a single point (poles) */
    size_t flipped_surfaces;  /**< surfaces reversed to agree with their neighbours */
    size_t boundary_edges;    /**< cell edges on the open boundary (no partner) */
    size_t refinements;       /**< adaptive: passes that refined a cell after the check */
    size_t limit_normals;     /**< vertex normals taken as a limit (degenerate points) */
    size_t welded_normals;    /**< corners given another patch's normal within
                                   normal_weld_degrees */
    uint32_t uniform_u, uniform_v; /**< adaptive: the gu x gv per-span uniform grid
                                        output instead (it had fewer triangles), or 0 */
} geom_surface_tess_stats;

/**
 * Tessellate n surfaces (each valid: GEOM_ERR_INVALID_ARG naming the surface
 * otherwise) into triangles, replacing the contents of mesh `out`.
 *
 * Structure. Each surface is cut into pieces at its discontinuities
 * (interior knots of multiplicity degree+1; the pieces only meet through
 * welding) and each piece into cells: its non-empty knot spans (uniform
 * mode with per_surface: the whole piece). Cells of one piece share their
 * edges. Unless no_weld is set, the boundary edges of all the
 * surfaces are welded: corners by exact position, and two boundary cell
 * edges with the same end points whose curves coincide (checked at three
 * interior points, in either direction, within 1e-9 of the model's size plus
 * 256 eps of its largest coordinate)
 * become one edge. A cell edge whose points all coincide (within the same
 * tolerance) is collapsed to one vertex (a pole, a cone's apex). Every edge is sampled once, at max of the counts the cells on
 * its two sides want, and both cells use those vertices: there are no
 * cracks and no T-junctions, and surfaces joined along such edges (the body
 * of the teapot) come out watertight.
 *
 * Cells. A cell whose edges carry exactly its own grid is triangulated as
 * the grid (each quad split along its shorter diagonal); otherwise its
 * interior grid is joined to the edge samples by strips, in parameter
 * space. Triangles with two corners on one collapsed vertex are dropped.
 *
 * Grid lines (adaptive, angle_degrees 0). Within a cell the lines of
 * constant u need not be evenly spaced: per column of cells of a piece,
 * sqrt of the largest |S_uu| normal to S_u across the column is sampled on
 * 32 equal parameter intervals, and where its largest value is more than
 * 1.8x its smallest, the lines are placed so that its integral is equal
 * between neighbouring lines (de Boor's equidistribution: every chord then
 * deviates about equally), each interval's density at least 0.3 of the
 * mean; rows along v likewise. The cells of a column and their edges
 * share the placement, so neighbours keep sharing edge samples; an edge
 * welded to an edge of another column keeps even lines on both unless
 * their placements agree. Rational weights that make the parametric speed
 * vary across a cell then no longer force the whole cell to the step of
 * its fastest part. Uniform mode, and the uniform grids below, use even
 * lines.
 *
 * Adaptive resolution. A cell whose second derivatives are bounded by
 * Muu, Muv, Mvv (the largest values sampled on a grid over the cell) gets
 * quads of hu x hv with the largest area that keeps Filip et al.'s bound
 * (hu^2 Muu + 2 hu hv Muv + hv^2 Mvv) / 8 within tol (hu/hv =
 * sqrt(Mvv/Muu)). Then every triangle is checked and the cells over the
 * tolerance (or the normal angle) are refined by the factor the measured
 * error asks for (1.1 sqrt(error/tol), between 1.25 and 4), up to 40 passes,
 * until all pass; GEOM_ERR_LIMIT if the triangle limit (or 65536 quads
 * along a cell) would be exceeded. If the passes run out first (a
 * tolerance below what the input's rounding allows), the result is
 * returned with the error it achieved in the report. When all pass (and
 * angle_degrees is 0), each cell's grid is replaced by the M x N grid with
 * the fewest quads whose triangles pass the same check (searched over M
 * within 4x of the current aspect ratio, the smallest passing N of each
 * by bisection), and the result is checked again as stitched.
 *
 * Never more triangles than a uniform grid. Then (adaptive, all cells
 * passing, angle_degrees 0) the per-span uniform grids are searched: gu x
 * gv on every knot-span cell of every surface, exactly what uniform mode
 * makes with grid_u = gu, grid_v = gv, per_surface 0 and the same
 * check_subdivisions. Every (gu, gv) whose triangle count can be below the
 * adaptive result's is either shown to fail (a boundary line's chords, or
 * a grid triangle that uniform mode makes too, over the tolerance by more
 * than the weld tolerance below, which covers the difference between
 * positions evaluated on a cell and the welded ones) or tessellated and
 * checked as uniform mode does; the one with the fewest triangles that
 * meets the tolerance with fewer triangles than adaptive is returned
 * instead (stats->uniform_u, uniform_v say which; the report is then
 * uniform mode's at that grid, identical). So the result never has more
 * triangles than a per-span uniform grid that meets the tolerance (no
 * monotonicity of the error in the grid is assumed), up to positions that
 * differ by more than the weld tolerance (edges welded on three points
 * that part elsewhere). Cost (BENCHMARKS.md): 4-10 % of the evaluations
 * for the NURBS sphere and the teapot at 1e-3 and 1e-4; most where many
 * grids are cheap and nothing bounds them from below, e.g. a single patch
 * with straight boundary lines (a bicubic bump: 0.27M evaluations on top
 * of 0.5M at 1e-3).
 *
 * Error check (both modes). Every triangle is compared with the exact
 * surface over its parameter-space image, at the barycentric lattice
 * points b (check_subdivisions per side, corners excluded): the surface
 * point S(sum b_i (u_i, v_i)) is measured against the mesh there, i.e. its
 * distance to the 3D triangle or, for half of a grid quad, to the nearer
 * of the quad's two triangles (the image of a quad's parameter diagonal is
 * no straight line); samples on the other sides (grid lines, cell edges)
 * are measured to that side, so mesh edges follow the surface's curves. A
 * one-sided Hausdorff distance at the samples (surface to mesh), never
 * larger than the distance to the triangle's point at the same
 * parameters: an uneven parametrisation (extreme rational weights) is no
 * longer counted as chordal error (a plane with weights 0.1..10: 0, two
 * triangles; a sphere octant with weights 0.1..10: 1.04x the triangles of
 * the ordinary octant at 1e-3, with weights 0.01..100 1.59x, through the
 * grid lines above; 7.8x with even lines). Fold guard: where the images of
 * the lattice's small triangles face against the triangle (the surface
 * turns back over it, which a distance to the mesh would hide), that
 * triangle's error is the equal-parameter distance. Triangles dropped at a
 * collapsed edge (pole) are not sampled. report (NULL allowed): max_error
 * (the largest distance), mean_error (the mean of the per-triangle
 * maxima), method GEOM_ERROR_SAMPLED, evaluations (surface evaluations for
 * the check, the sizing and the searches).
 *
 * Quads are split along the shorter diagonal; a near tie (within 8 weld
 * tolerances, e.g. every quad of a surface of revolution) takes the
 * diagonal from the quad's first corner (lowest u, v), so the split does
 * not depend on rounding.
 *
 * Output. Positions of welded vertices are computed once (on the first
 * surface that owns the edge). Triangles are counter-clockwise in parameter
 * space, i.e. their normals follow Su x Sv of their surface (after any flip
 * for consistency). Channels, as asked in options->attributes, are CORNER
 * channels whose values are deduplicated exactly: "normal" (3) from
 * geom_surface_normal on the triangle's own surface and cell (so a cone's
 * apex or a crease keeps one normal per side; negated on flipped surfaces),
 * "uv" (2), "tangent" (4: unit dP/du, and w = +-1 such that
 * w * (normal x tangent) points along dP/dv; at a degenerate point the
 * limit direction); and the FACE channel "surface" (1: the index in
 * `surfaces` of the face's surface, as a double). The mesh is built with geom_mesh_build (which can
 * report repairs of non-manifold input, e.g. three patches on one edge).
 *
 * stats (NULL allowed) receives counts; diag the reason for a failure.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL pointers, n == 0, an
 * invalid surface, bad options); GEOM_ERR_LIMIT; GEOM_ERR_NOMEM; and
 * geom_mesh_build's.
 */
GEOM_API geom_status geom_surface_tessellate(const geom_nurbs_surface *surfaces, size_t n,
                                    const geom_surface_tess_options *options, geom_mesh *out,
                                    geom_error_report *report, geom_surface_tess_stats *stats,
                                    geom_diag *diag);

/**
 * The number of triangles geom_surface_tessellate would make for the n
 * surfaces with these options (NULL: defaults), before doing it, so that
 * callers can refuse an output that would not fit. Uniform mode:
 * 2 * grid_u * grid_v per non-empty knot-span cell (or per surface with
 * per_surface), an upper bound that is exact unless cells collapse: the
 * triangles of a degenerate edge (a sphere's poles) are dropped from the
 * mesh but counted here (NURBS sphere at 5 x 3 per span: 240 estimated,
 * 200 made). Adaptive mode: an estimate from |S_uu|, |S_uv|, |S_vv| on a
 * 4x4 grid per knot span (a flat triangle of parameter size h deviates by
 * about |S''| h^2 / 8 from the surface); typically within a factor 2 of the
 * count made, not a bound. Costs 16 derivative evaluations per span.
 * GEOM_OK; GEOM_ERR_INVALID_ARG for NULL triangles, NULL s with n > 0, or an
 * invalid surface.
 */
GEOM_API geom_status geom_surface_tess_estimate(const geom_nurbs_surface *s, size_t n,
                                                const geom_surface_tess_options *opt,
                                                double *triangles);

/* ------------------------------------------------------------ batches */

/**
 * geom_surface_eval (normals == 0) or geom_surface_normal (normals != 0)
 * at n parameter pairs uv (2*n doubles: u0 v0 u1 v1 ...) in one call (for
 * bindings; same results): out receives 3*n doubles; a failing row is NaN
 * with its geom_status in status (n int32 values, NULL allowed), counted in
 * *n_failed (NULL allowed). Returns GEOM_OK, or GEOM_ERR_INVALID_ARG for
 * NULL s/uv/out with n > 0.
 */
GEOM_API geom_status geom_surface_eval_many(const geom_nurbs_surface *s, size_t n, const double *uv,
                                            unsigned flags, int normals, double *out,
                                            int32_t *status, size_t *n_failed);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_SURFACE_H */
