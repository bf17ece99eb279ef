/*
 * libgeom step: ISO 10303-21 ("STEP Part 21") files read into a boundary
 * representation (solids, shells, faces, loops, edges, vertices over exact
 * curves and surfaces), and the watertight trimmed tessellation of that
 * B-rep into one geom_mesh.
 *
 * References: ISO 10303-21:2016 (the exchange structure: tokens, escapes,
 * complex instances); ISO 10303-42 (geometric and topological
 * representation: the entities and their parameterisations below);
 * ISO 10303-41 (units); L. Piegl and W. Tiller, The NURBS Book (NURBS
 * evaluation); J. R. Shewchuk, "Delaunay refinement algorithms for
 * triangular mesh generation", CGTA 22, 2002, and L. P. Chew, "Constrained
 * Delaunay triangulations", Algorithmica 4, 1989 (the face meshing);
 * S. W. Sloan, "A fast algorithm for generating constrained Delaunay
 * triangulations", Computers & Structures 47(3), 1993 (segment recovery).
 *
 * Conventions:
 *  - Lengths come out in millimetres by default (the unit of most CAD files,
 *    and what OpenCASCADE and gmsh use); geom_step_read_options::unit_metres
 *    chooses another output unit. Every file length is converted from the
 *    unit of its representation context (SI units with any prefix, and
 *    CONVERSION_BASED_UNIT such as INCH or FOOT through its conversion
 *    factor). Plane angles are converted to radians.
 *  - Every surface keeps its STEP parameterisation (so PCURVEs apply
 *    unchanged, with angles in radians): see geom_step_surface_eval.
 *  - Coordinates are STEP's, which is Z-up; tools converting to a Y-up
 *    format (glTF) rotate.
 *  - Nothing prints or keeps global state; every function is reentrant.
 */
#ifndef GEOM_STEP_H
#define GEOM_STEP_H

#include "geom/core.h"
#include "geom/curve.h"
#include "geom/mesh.h"
#include "geom/surface.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ B-rep */

/** Curve kinds (geom_brep_curve::type). */
typedef enum geom_brep_curve_type {
    GEOM_BREP_CURVE_LINE = 0,    /**< origin + t * dir (dir with the VECTOR's magnitude) */
    GEOM_BREP_CURVE_CIRCLE = 1,  /**< origin + r (cos t x + sin t y), t in radians */
    GEOM_BREP_CURVE_ELLIPSE = 2, /**< origin + a cos t x + b sin t y */
    GEOM_BREP_CURVE_NURBS = 3    /**< nurbs (POLYLINE: degree 1, knots 0, 1, ..., n-1) */
} geom_brep_curve_type;

/** A 3D curve, or a 2D parameter-space curve of a PCURVE (z = 0). */
typedef struct geom_brep_curve {
    geom_brep_curve_type type;
    uint64_t entity;   /**< the STEP instance id (#n) it came from */
    int dim;           /**< 3, or 2 for a pcurve */
    double origin[3], x[3], y[3], z[3]; /**< placement (unit, orthogonal x, y, z) */
    double dir[3];     /**< LINE: direction times magnitude */
    double r1, r2;     /**< CIRCLE radius; ELLIPSE semi-axes */
    geom_nurbs_curve nurbs; /**< NURBS: arrays owned by the B-rep */
    size_t nknots;     /**< NURBS: knot count */
} geom_brep_curve;

/** Surface kinds (geom_brep_surface::type) with their (u, v) parameterisation. */
typedef enum geom_brep_surface_type {
    GEOM_BREP_SURFACE_PLANE = 0,      /**< o + u x + v y */
    GEOM_BREP_SURFACE_CYLINDER = 1,   /**< o + r (cos u x + sin u y) + v z */
    GEOM_BREP_SURFACE_CONE = 2,       /**< o + (r + v tan a)(cos u x + sin u y) + v z */
    GEOM_BREP_SURFACE_SPHERE = 3,     /**< o + r cos v (cos u x + sin u y) + r sin v z */
    GEOM_BREP_SURFACE_TORUS = 4,      /**< o + (R + r cos v)(cos u x + sin u y) + r sin v z */
    GEOM_BREP_SURFACE_NURBS = 5,      /**< nurbs */
    GEOM_BREP_SURFACE_REVOLUTION = 6, /**< curve(v) turned by u radians about (o, z) */
    GEOM_BREP_SURFACE_EXTRUSION = 7   /**< curve(u) + v dir */
} geom_brep_surface_type;

typedef struct geom_brep_surface {
    geom_brep_surface_type type;
    uint64_t entity;
    double origin[3], x[3], y[3], z[3];
    double r1;       /**< radius (CYLINDER, CONE at v = 0, SPHERE), major radius (TORUS) */
    double r2;       /**< minor radius (TORUS), semi-angle in radians (CONE) */
    double dir[3];   /**< EXTRUSION: the extrusion vector */
    uint32_t curve;  /**< REVOLUTION / EXTRUSION: the swept curve (index into curves) */
    geom_nurbs_surface nurbs; /**< NURBS: arrays owned by the B-rep */
    int u_periodic, v_periodic; /**< 1 when the parameter is an angle (period 2 pi) */
} geom_brep_surface;

typedef struct geom_brep_vertex {
    double p[3];
    uint64_t entity;
} geom_brep_vertex;

/** An EDGE_CURVE: from vertex v0 to v1 along curve (reversed when same_sense
 *  is 0: the edge then runs against the curve's parameter), between
 *  curve parameters t0 (at v0) and t1 (at v1). pcurve[k] / pcurve_surface[k]
 *  (GEOM_INVALID_INDEX when absent) are the parameter-space images the file
 *  gave (SURFACE_CURVE / SEAM_CURVE), in the same parameter as the curve. */
typedef struct geom_brep_edge {
    uint32_t v0, v1;
    uint32_t curve;
    int same_sense;
    double t0, t1;
    uint32_t pcurve[2];
    uint32_t pcurve_surface[2];
    uint64_t entity;
} geom_brep_edge;

/** An ORIENTED_EDGE of a loop: the edge, reversed when `reversed` is 1. */
typedef struct geom_brep_coedge {
    uint32_t edge;
    int reversed;
} geom_brep_coedge;

/** FACE_OUTER_BOUND / FACE_BOUND: coedges first .. first+n-1 (an EDGE_LOOP;
 *  n == 0 and vertex set for a VERTEX_LOOP), reversed when orientation is 0. */
typedef struct geom_brep_loop {
    uint32_t first, n;
    int outer;
    int orientation;
    uint32_t vertex;
    uint64_t entity;
} geom_brep_loop;

/** An ADVANCED_FACE (or FACE_SURFACE): loops first .. first+nloops-1. Its
 *  outward side is the surface normal (Su x Sv) when same_sense is 1. */
typedef struct geom_brep_face {
    uint32_t surface;
    int same_sense;
    uint32_t first_loop, nloops;
    uint32_t shell;
    uint64_t entity;
} geom_brep_face;

/** A CLOSED_SHELL or OPEN_SHELL: faces first .. first+n-1. */
typedef struct geom_brep_shell {
    uint32_t first_face, nfaces;
    int closed;
    uint32_t solid;   /**< GEOM_INVALID_INDEX for a SHELL_BASED_SURFACE_MODEL's shells */
    uint64_t entity;
} geom_brep_shell;

/** A MANIFOLD_SOLID_BREP or BREP_WITH_VOIDS (shells first .. first+n-1, the
 *  outer one first), placed by the assembly transforms. */
typedef struct geom_brep_solid {
    uint32_t first_shell, nshells;
    uint64_t entity;
} geom_brep_solid;

/** An entity the reader met and could not use (unsupported type, or
 *  unsupported use of a supported one): its id, type and the reason. */
typedef struct geom_brep_issue {
    uint64_t entity;
    char type[48];
    char reason[80];
} geom_brep_issue;

/**
 * A B-rep as read: plain arrays the caller may walk (indices are uint32,
 * GEOM_INVALID_INDEX where absent). Assembly instances are flattened: a
 * part placed twice appears twice, each copy with its own transformed
 * geometry. Owned by the reader; free with geom_step_destroy.
 */
typedef struct geom_brep {
    size_t nsolids, nshells, nfaces, nloops, ncoedges, nedges, nvertices, ncurves, nsurfaces;
    geom_brep_solid *solids;
    geom_brep_shell *shells;
    geom_brep_face *faces;
    geom_brep_loop *loops;
    geom_brep_coedge *coedges;
    geom_brep_edge *edges;
    geom_brep_vertex *vertices;
    geom_brep_curve *curves;
    geom_brep_surface *surfaces;
    size_t nissues;          /**< unsupported entities (the first 64 are listed) */
    geom_brep_issue *issues;
    size_t nskipped_faces;   /**< faces left out because their geometry is unsupported */
    double unit_metres;      /**< metres per output length unit */
    size_t ninstances;       /**< placed part instances (1 for a single part) */
    void *internal_;
} geom_brep;

/** Read options; valid when zero-initialised. */
typedef struct geom_step_read_options {
    /** Metres per output length unit: 0 means 0.001 (millimetres). */
    double unit_metres;
    /** Largest input size in bytes (0: 1 GiB) and nesting depth of
     *  parameter lists (0: 64): GEOM_ERR_LIMIT beyond. */
    size_t max_bytes;
    int max_depth;
    /** Nonzero: fail with GEOM_ERR_PARSE at the first unsupported face
     *  instead of listing it in issues and leaving it out. */
    int strict;
    const geom_allocator *alloc;
} geom_step_read_options;

/**
 * Parse ISO 10303-21 text (size bytes, no NUL needed) and map its B-rep
 * bodies (MANIFOLD_SOLID_BREP, BREP_WITH_VOIDS, SHELL_BASED_SURFACE_MODEL,
 * reached through the representations and their assembly transforms:
 * REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION / ITEM_DEFINED_TRANSFORMATION
 * (as used by CONTEXT_DEPENDENT_SHAPE_REPRESENTATION) and MAPPED_ITEM, whose
 * placements may be AXIS2_PLACEMENT_3D or CARTESIAN_TRANSFORMATION_OPERATOR(_3D):
 * axis1/2/3 by ISO 10303-42's base_axis, local origin, uniform scale, and
 * mirrors, whose faces are turned back outward) to *out. Supported geometry: PLANE, CYLINDRICAL_SURFACE, CONICAL_SURFACE,
 * SPHERICAL_SURFACE, TOROIDAL_SURFACE, SURFACE_OF_REVOLUTION,
 * SURFACE_OF_LINEAR_EXTRUSION, B_SPLINE_SURFACE_WITH_KNOTS (and the complex
 * rational form), LINE, CIRCLE, ELLIPSE, B_SPLINE_CURVE_WITH_KNOTS
 * (rational too), POLYLINE, TRIMMED_CURVE (its basis curve), SURFACE_CURVE,
 * SEAM_CURVE and PCURVE. A face on any other surface is listed in
 * (*out)->issues with its id and type and left out (or, with strict, fails).
 *
 * Parser: header and data sections, simple and complex instances, strings
 * with '' and \\ and the \X\hh, \X2\...\X0\, \X4\...\X0\ and \S\ escapes
 * (decoded to UTF-8), comments, $ and *, enumerations, typed parameters,
 * binary literals, forward references. Errors name source:line:column:
 * GEOM_ERR_PARSE for malformed text, a duplicate instance id, a dangling
 * reference (a #n never defined) or an entity with the wrong parameters;
 * GEOM_ERR_LIMIT beyond max_bytes / max_depth; GEOM_ERR_NOMEM.
 * source_name (NULL: "<memory>") names the input in diagnostics.
 */
GEOM_API geom_status geom_step_read_memory(const void *data, size_t size, const char *source_name,
                                           const geom_step_read_options *options, geom_brep **out,
                                           geom_diag *diag);

/** geom_step_read_memory on the contents of the file at path (GEOM_ERR_IO
 *  when it cannot be read). */
GEOM_API geom_status geom_step_read(const char *path, const geom_step_read_options *options,
                                    geom_brep **out, geom_diag *diag);

/** Free a B-rep. NULL is a no-op. */
GEOM_API void geom_step_destroy(geom_brep *b);

/** S(u, v) (3 doubles) of surface s of b, and if du/dv are not NULL the
 *  first partial derivatives. GEOM_ERR_INVALID_ARG for a bad index,
 *  GEOM_ERR_DOMAIN outside a NURBS surface's domain. */
GEOM_API geom_status geom_step_surface_eval(const geom_brep *b, uint32_t s, double u, double v,
                                            double p[3], double du[3], double dv[3]);

/** C(t) (dim doubles) of curve c of b. */
GEOM_API geom_status geom_step_curve_eval(const geom_brep *b, uint32_t c, double t, double *p);

/* ----------------------------------------------------------- tessellation */

/** Tessellation options; valid when zero-initialised. */
typedef struct geom_brep_tess_options {
    /** Chordal tolerance in output units (> 0); 0 means 1e-3 times the
     *  diagonal of the model's bounding box. */
    double tolerance;
    /** If > 0, also refine until the surface normals at the corners of
     *  every triangle are within this angle (degrees) of each other. */
    double angle_degrees;
    /** OR of GEOM_SURFACE_ATTR_NORMAL (CORNER "normal"), GEOM_SURFACE_ATTR_UV
     *  (CORNER "uv", the face's surface parameters) and GEOM_SURFACE_ATTR_SOURCE
     *  (FACE "face": the B-rep face index of each triangle, as a double). */
    unsigned attributes;
    /** Largest number of triangles (0: 2^24): GEOM_ERR_LIMIT beyond. */
    size_t max_triangles;
    const geom_allocator *alloc;
} geom_brep_tess_options;

/** Per-face results of a tessellation. */
typedef struct geom_brep_face_report {
    double chordal_error;  /**< largest sampled distance triangle - surface (the
                            *   surface displaced by the edge gap interpolated
                            *   from the triangle's corners, see
                            *   geom_step_tessellate) */
    double edge_gap;       /**< largest |C(t) - S(uv(t))| over its boundary samples */
    size_t triangles;
    double seconds;        /**< processor time (clock()) of its last meshing pass */
    int status;            /**< GEOM_OK, or why the face was left out */
} geom_brep_face_report;

/** Totals of a tessellation. */
typedef struct geom_brep_tess_stats {
    size_t faces, faces_failed, triangles, vertices;
    size_t edge_samples;      /**< vertices on edges (shared by both faces) */
    double edge_gap;          /**< largest edge gap over all faces */
    double edge_error;        /**< largest sampled distance edge chord - 3D curve */
    size_t open_edges;        /**< mesh boundary edges after building (0: closed) */
    size_t nonmanifold_edges; /**< repairs geom_mesh_build reported */
    double seconds;           /**< processor time (clock()) of the whole tessellation */
} geom_brep_tess_stats;

/**
 * Tessellate every face of b into triangles, replacing the contents of out.
 *
 * Each edge is sampled once in 3D, adaptively until every chord is within
 * the tolerance of the curve (sampled at the chord's quarter points), and
 * both of its faces use those vertices, so a closed shell comes out closed.
 * Each face's loops are taken to its (u, v) domain: the edge samples are
 * inverted onto the surface (closed form for the analytic surfaces; Newton
 * iteration from the PCURVE's image, or from a grid, for NURBS), unwrapped
 * across the seams of periodic surfaces, and joined through poles; two
 * loops that close only after a whole period (the side of a cylinder
 * between two circles, with no seam edge) are joined into one through an
 * added seam, sampled to the tolerance and used on both of its sides. The
 * face is meshed there by a constrained Delaunay triangulation (exact
 * geom_orient2d / geom_incircle, in coordinates scaled by the surface's
 * metric) and refined by inserting the worst sample point of every
 * triangle whose chordal error (the distance between the triangle and the
 * surface at 7 barycentric samples: the centroid, the edge midpoints and
 * three interior points; where a corner is an edge point lying off the
 * surface, by the file's own gap between an edge curve and its surface, the
 * surface is displaced there by that gap, interpolated linearly over the
 * triangle, so that a gap the file carries is reported as edge_gap and not
 * refined for in vain) or corner-normal angle exceeds the tolerance: at
 * the triangle's circumcentre when that lies inside the face away from its
 * boundary (Ruppert), else at the worst sample. Where the worst sample is
 * on the face's boundary, the edge piece is split at its parameter
 * midpoint (for both faces of the edge) and the faces meshed again, up to
 * 5 more passes. Triangles are oriented to the face's outward side (same_sense
 * and the loop orientation), so closed solids get outward normals.
 *
 * The mesh is built once with geom_mesh_build. report (NULL allowed):
 * max_error (largest chordal error over faces and edges, sampled),
 * mean_error, method GEOM_ERROR_SAMPLED, evaluations. faces (NULL allowed,
 * else b->nfaces entries) receives the per-face figures; stats the totals.
 * A face that cannot be meshed (a loop that cannot be closed in its domain)
 * is left out and counted in stats->faces_failed with its status in faces.
 * Statuses: GEOM_OK, GEOM_ERR_INVALID_ARG, GEOM_ERR_LIMIT, GEOM_ERR_NOMEM
 * and geom_mesh_build's.
 */
GEOM_API geom_status geom_step_tessellate(const geom_brep *b, const geom_brep_tess_options *options,
                                          geom_mesh *out, geom_error_report *report,
                                          geom_brep_face_report *faces, geom_brep_tess_stats *stats,
                                          geom_diag *diag);

/**
 * The number of triangles geom_step_tessellate(b, options, ...) would make,
 * estimated before the work (for callers that refuse an output too large:
 * geom-tessellate's --max-triangles and --max-memory). Per face: its
 * parameter box, from 17 points of each of its edges inverted onto its
 * surface (unwrapped across the seams of periodic surfaces, at most one
 * period wide); over that box the surface module's per-patch estimate
 * (geom_surface_tess_estimate's adaptive model: a flat triangle of
 * parameter size h deviates by about |S''| h^2 / 8, on an 8 x 8 sample grid,
 * or 4 samples per knot span for B-spline surfaces) from the surface's
 * second derivatives (exact for B-splines, central differences of the
 * closed-form first derivatives for planes, cylinders, cones, spheres,
 * tori, surfaces of revolution and of linear extrusion); plus the boundary
 * samples of its edges (each edge's chords from its curvature at 16
 * points, and at least the tessellator's initial pieces) less 2. The
 * tolerance is options->tolerance or its default (NULL options: defaults);
 * options->angle_degrees is not modelled (an angle bound adds triangles
 * the estimate does not count). NOT an upper bound: measured 0.6-2.5 times
 * the count made on gmsh-doc's STEP files (BENCHMARKS.md). Costs about
 * 17 point inversions per edge use and 64-65,536 derivative evaluations per
 * face, far less than the tessellation. per_face (b->nfaces doubles, NULL
 * allowed) receives each face's estimate.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL b or triangles, a negative
 * or non-finite tolerance); GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_step_tess_estimate(const geom_brep *b, const geom_brep_tess_options *options,
                                             double *triangles, double *per_face);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_STEP_H */
