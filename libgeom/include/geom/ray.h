/*
 * libgeom ray: ray intersection for every representation, with one contract.
 *
 * A query takes a geom_ray (core.h: origin + t*dir, t in [tmin, tmax], both
 * ends inclusive, t in units of dir as given, dir not normalised) and a
 * built geom_ray_scene, and answers
 *   - the closest hit            (geom_ray_scene_closest),
 *   - whether anything is hit    (geom_ray_scene_any: shadow rays),
 *   - every hit sorted by t with entering/leaving flags (geom_ray_scene_all:
 *     what CSG and inside/outside counting need).
 *
 * A hit (geom_ray_hit) carries t, the point, the geometric normal, the
 * shading normal, (u, v), the primitive and object indices, and bounds on
 * the error of t and of the point. geom_ray_offset_origin() starts a
 * secondary ray off the surface by that bound (Waechter and Binder, "A Fast
 * and Robust Method for Avoiding Self-Intersection", Ray Tracing Gems ch. 6)
 * so that it never re-hits its own surface at any scale (tested from 1e-4 to
 * 1e7).
 *
 * Conventions (the same for every representation, so answers are unique):
 *  - normals: the geometric normal ng is unit length and has the stored
 *    orientation whatever side the ray comes from: outward for closed solids
 *    (a quadric's inside is F < 0, a torus's inside is the tube), dP/du x
 *    dP/dv for parametric surfaces, the winding's normal (v1-v0) x (v2-v0)
 *    for triangles and polygons, +normal for planes and disks, the gradient
 *    direction (outward = increasing f) for implicit surfaces and volumes
 *    with inside f < iso (a volume's inside may be f > iso instead:
 *    geom_ray_volume_options). `enter` is d.ng < 0; for solids with a tangent
 *    (double) root the two coincident hits are reported enter then leave.
 *  - (u, v): the barycentric weights of vertices 1 and 2 for triangles (and
 *    for the fan triangle (v0, v_i, v_i+1) of a polygon or mesh face, prim
 *    being the face); the parameters for parametric surfaces; per analytic
 *    shape as documented at its geom_ray_scene_add_* function.
 *  - a hit exactly on an edge or a vertex shared by triangles of a mesh is
 *    reported by exactly one of them (also in geom_ray_scene_all), whichever
 *    side the ray comes from: watertight (no leaks) and no double hits.
 *  - a ray whose origin or direction is NaN/Inf, whose direction is zero, or
 *    whose tmin/tmax is NaN gives GEOM_ERR_INVALID_ARG and no hit: never a
 *    crash, never a false hit. tmin > tmax is a valid, empty query.
 *
 * The scene is built once (geom_ray_scene_build: bounds, inverse transforms,
 * BVHs for meshes, Bezier decompositions for surfaces) and is then read-only:
 * any number of threads may query it at once.
 */
#ifndef GEOM_RAY_H
#define GEOM_RAY_H

#include "geom/core.h"
#include "geom/implicit.h"
#include "geom/mesh.h"
#include "geom/surface.h"

#ifdef __cplusplus
extern "C" {
#endif

/* --------------------------------------------------------------------- hits */

/** One intersection of a ray with a surface. */
typedef struct geom_ray_hit {
    double t;           /**< ray parameter (units of dir as given) */
    geom_vec3 point;    /**< the hit point (computed on the surface, see p_error) */
    geom_vec3 ng;       /**< unit geometric normal, stored orientation */
    geom_vec3 ns;       /**< unit shading normal (interpolated/analytic; = ng if none) */
    double u, v;        /**< surface parameters or barycentrics (see conventions) */
    uint32_t prim;      /**< primitive index within the object (triangle/face/patch), else 0 */
    uint32_t object;    /**< 0-based index of the top-level object (geom_ray_scene_set_objects) */
    double t_error;     /**< bound on |t - exact t| (first order, see each representation) */
    geom_vec3 p_error;  /**< per-component bound on |point - exact surface point| */
    int enter;          /**< 1 if the ray enters the surface here (d.ng < 0), 0 if it leaves */
} geom_ray_hit;

/**
 * Origin for a secondary ray leaving the hit point in direction `dir` (which
 * side of the surface it leaves to is the sign of dir.ng): the point moved
 * along +-ng by the projection of the point's error bound onto the normal
 * (|ng.x| pe.x + |ng.y| pe.y + |ng.z| pe.z, pbrt's rule), plus a fixed
 * integer number of ulps of each coordinate away from the surface (Waechter
 * and Binder's int_scale, 64 ulps in double) and, for coordinates near
 * zero, an absolute 2^-40 * scale floor where scale is the largest
 * coordinate magnitude of the point (their float_scale rule). The new ray
 * then starts at tmin = 0. A zero or non-finite dir gives the point moved
 * along +ng. Never NaN for a finite hit.
 */
GEOM_API geom_vec3 geom_ray_offset_origin(const geom_ray_hit *hit, geom_vec3 dir);

/** GEOM_OK if r is a valid query ray (finite origin and direction, nonzero
 *  direction, tmin and tmax not NaN), GEOM_ERR_INVALID_ARG otherwise. */
GEOM_API geom_status geom_ray_check(const geom_ray *r);

/**
 * Watertight ray-triangle test (Woop, Benthin and Wald, "Watertight
 * Ray/Triangle Intersection", JCGT 2013) in double, with the edge
 * functions' signs made exact (Shewchuk's orient2d on the sheared
 * coordinates when the double value is within its rounding bound) and a
 * tie-breaking rule for zero edge functions (the directed edge owns the
 * zero when its sheared direction has dy > 0, or dy == 0 and dx > 0), so
 * that a ray through an edge or vertex shared by the triangles of a closed,
 * consistently oriented mesh hits exactly one of them.
 * v0, v1, v2: 3 doubles each. On a hit in [tmin, tmax] returns 1 and fills
 * hit (t, point, ng, ns = ng, u, v = barycentric weights of v1 and v2,
 * enter, error bounds; prim and object = 0). Returns 0 on a miss, for a
 * degenerate (zero-area in projection) triangle and for an invalid ray.
 */
GEOM_API int geom_ray_triangle(const geom_ray *r, const double v0[3], const double v1[3],
                               const double v2[3], geom_ray_hit *hit);

/**
 * Real roots of the polynomial c[0] + c[1] x + ... + c[deg] x^deg (deg <= 8)
 * in [lo, hi] (finite), sorted, with multiplicity-2 roots (tangencies)
 * reported twice. Method: the critical points (roots of the derivative,
 * recursively) split [lo, hi] into monotone pieces; a piece whose ends have
 * opposite signs holds exactly one root, found by safeguarded Newton /
 * bisection to full double precision; a critical point where |p| is within
 * the running error bound of Horner's evaluation (Higham 5.1) is a double
 * root. No root with a sign change is missed, and no root is reported where
 * |p| exceeds its error bound. roots: deg doubles. Returns the count.
 */
GEOM_API size_t geom_ray_poly_roots(const double *c, int deg, double lo, double hi, double *roots);

/* -------------------------------------------------------------------- scene */

/** Representation of an object. */
typedef enum geom_ray_kind {
    GEOM_RAY_PLANE = 1,
    GEOM_RAY_DISK,
    GEOM_RAY_BOX,
    GEOM_RAY_OBOX,
    GEOM_RAY_SPHERE,
    GEOM_RAY_QUADRIC,
    GEOM_RAY_TORUS,
    GEOM_RAY_TRIANGLE,
    GEOM_RAY_POLYGON,
    GEOM_RAY_MESH,
    GEOM_RAY_SURFACE,
    GEOM_RAY_SUBDIV,
    GEOM_RAY_IMPLICIT,
    GEOM_RAY_VOLUME,
    GEOM_RAY_CSG,
    GEOM_RAY_INSTANCE,
    GEOM_RAY_GROUP
} geom_ray_kind;

/** Name of a kind ("sphere", "mesh", ...); "unknown" for other values. */
GEOM_API const char *geom_ray_kind_name(geom_ray_kind k);

/** CSG operations (Roth 1982: combination of the children's hit intervals). */
typedef enum geom_ray_csg_op {
    GEOM_RAY_CSG_UNION = 1,
    GEOM_RAY_CSG_INTERSECTION,
    GEOM_RAY_CSG_DIFFERENCE /**< first child minus second */
} geom_ray_csg_op;

/** A scene of objects (opaque). */
typedef struct geom_ray_scene geom_ray_scene;

/** A new empty scene (alloc NULL: libc). NULL when out of memory. */
GEOM_API geom_ray_scene *geom_ray_scene_create(const geom_allocator *alloc);
/** Free the scene and everything it owns. NULL is a no-op. */
GEOM_API void geom_ray_scene_destroy(geom_ray_scene *s);

/*
 * Adding objects. Each function adds one node and returns its id in *id
 * (NULL allowed). Geometry is copied (meshes, surfaces and volumes are
 * borrowed: see each function). Nodes are in their own local frame until
 * geom_ray_scene_set_transform gives them one. Statuses:
 * GEOM_ERR_INVALID_ARG for NULL/NaN/Inf input or an out-of-range child id,
 * GEOM_ERR_DEGENERATE for zero radii/normals/extents, GEOM_ERR_NOMEM.
 * Adding after geom_ray_scene_build is allowed; build again before querying.
 */

/** Plane through point with normal n (not necessarily unit): unbounded,
 *  two-sided, ng = n/|n|; a half-space solid (inside is (x-point).n < 0) in
 *  CSG. (u, v): coordinates of the point along two fixed orthonormal
 *  tangents of the plane, relative to `point`. */
GEOM_API geom_status geom_ray_scene_add_plane(geom_ray_scene *s, const double point[3],
                                              const double n[3], uint32_t *id);
/** Disk of `radius` > 0 about center in the plane with normal n. (u, v):
 *  polar radius / radius in [0, 1] and angle / (2 pi) in [0, 1). Not closed. */
GEOM_API geom_status geom_ray_scene_add_disk(geom_ray_scene *s, const double center[3],
                                             const double n[3], double radius, uint32_t *id);
/** Axis-aligned box [min, max] (min <= max, a zero extent is allowed: a
 *  flat box). Closed solid. (u, v): the hit face's two coordinates scaled
 *  to [0, 1]; prim: face index 0..5 = -x, +x, -y, +y, -z, +z. */
GEOM_API geom_status geom_ray_scene_add_box(geom_ray_scene *s, const double min[3],
                                            const double max[3], uint32_t *id);
/** Oriented box: center, three axes (9 doubles, orthogonal, not necessarily
 *  unit; their lengths are ignored) and half-extents >= 0 along them.
 *  As the box, in the frame of the normalised axes. */
GEOM_API geom_status geom_ray_scene_add_obox(geom_ray_scene *s, const double center[3],
                                             const double axes[9], const double half[3],
                                             uint32_t *id);
/**
 * Sphere, by the stable formulation of Haines, Guenther and Akenine-Moeller
 * ("Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems
 * ch. 7): the discriminant from the distance of the line to the centre, the
 * two roots from q = -(b + sign(b) sqrt(D)) as c/q and q/a, so a small
 * sphere far from the origin keeps its digits. (u, v): longitude / (2 pi)
 * in [0, 1) about +z, (z-colatitude) / pi in [0, 1]. The point is projected
 * onto the sphere; p_error is then ~5 ulp of |center| + radius.
 */
GEOM_API geom_status geom_ray_scene_add_sphere(geom_ray_scene *s, const double center[3],
                                               double radius, uint32_t *id);
/**
 * General quadric F(x) = a x^2 + b y^2 + c z^2 + 2d xy + 2e yz + 2f xz +
 * 2g x + 2h y + 2i z + j = 0 (coefficients q[10] = a..j), inside F < 0,
 * ng = grad F / |grad F|. clip (NULL: none): 6 doubles min, max of a box
 * to which the surface is restricted; capped != 0 closes it with the box's
 * faces where they are inside the quadric (the solid {F < 0} inter box:
 * capped cylinders and cones). Roots of the quadratic along the ray are
 * computed stably then polished by one Newton step on F at the hit, with
 * t_error = (|F| + its evaluation bound) / |dF/dt| (large at tangency).
 * (u, v): the local point's atan2(y, x) / (2 pi) in [0, 1) and z.
 * geom_ray_quadric_make gives the coefficients of the usual shapes.
 */
GEOM_API geom_status geom_ray_scene_add_quadric(geom_ray_scene *s, const double q[10],
                                                const double clip[6], int capped, uint32_t *id);

/** Shapes for geom_ray_quadric_make, all about the z axis through the origin. */
typedef enum geom_ray_quadric_shape {
    GEOM_RAY_QUADRIC_ELLIPSOID = 1,  /**< p = {rx, ry, rz}: x^2/rx^2 + ... = 1 */
    GEOM_RAY_QUADRIC_CYLINDER,       /**< p = {r}: x^2 + y^2 = r^2 */
    GEOM_RAY_QUADRIC_CONE,           /**< p = {k}: x^2 + y^2 = (k z)^2 (apex at 0) */
    GEOM_RAY_QUADRIC_PARABOLOID,     /**< p = {k}: x^2 + y^2 = k z */
    GEOM_RAY_QUADRIC_HYPERBOLOID1,   /**< p = {a, c}: (x^2 + y^2)/a^2 - z^2/c^2 = 1 (one sheet) */
    GEOM_RAY_QUADRIC_HYPERBOLOID2    /**< p = {a, c}: z^2/c^2 - (x^2 + y^2)/a^2 = 1 (two sheets,
                                          inside = within the sheets, |z| large) */
} geom_ray_quadric_shape;

/** Coefficients q[10] of a standard quadric (parameters as listed above,
 *  each > 0), with the inside F < 0 being the solid side (the tube of a
 *  cylinder, the cone's double nappe interior, between the sheets' outside
 *  for the two-sheet hyperboloid: F = 1 + (x^2+y^2)/a^2 - z^2/c^2).
 *  GEOM_ERR_DOMAIN for a non-positive parameter, INVALID_ARG for NULL. */
GEOM_API geom_status geom_ray_quadric_make(geom_ray_quadric_shape shape, const double *p,
                                           double q[10]);

/**
 * Torus about the z axis centred at the origin: major radius R > 0, minor
 * r > 0 (r > R gives a spindle torus, also handled). The quartic in t is
 * formed about the ray point closest to the centre (t shifted, direction
 * normalised, so coefficients stay small) and solved by geom_ray_poly_roots
 * on the interval where the ray is within R + r of the centre, then each
 * root is polished by Newton on the torus function in the original frame.
 * Grazing rays: a tangency within the evaluation error bound is a double
 * root (reported, not missed); no root is reported without a sign change
 * or a value within that bound (no phantom roots). t_error as the quadric.
 * (u, v): angle about z / (2 pi) and angle about the tube / (2 pi), in [0, 1).
 */
GEOM_API geom_status geom_ray_scene_add_torus(geom_ray_scene *s, double major, double minor,
                                              uint32_t *id);
/** One triangle (9 doubles), geom_ray_triangle's test. Not closed. */
GEOM_API geom_status geom_ray_scene_add_triangle(geom_ray_scene *s, const double v[9], uint32_t *id);
/** Planar polygon of n >= 3 vertices (3*n doubles; the plane is Newell's
 *  normal through the centroid). Inside by the non-zero winding number of
 *  the polygon around the ray in the sheared frame of geom_ray_triangle,
 *  with exact orientation signs and the same edge ownership rule. (u, v):
 *  the hit's coordinates along two orthonormal tangents of the plane
 *  (geom__frame of the normal: Duff et al. 2017) relative to v0; prim 0.
 *  Not closed. */
GEOM_API geom_status geom_ray_scene_add_polygon(geom_ray_scene *s, const double *v, size_t n,
                                                uint32_t *id);
/**
 * Triangle mesh: the mesh's faces (polygons fan-triangulated from their
 * first vertex) in a BVH from the spatial module (SAH), traversed with Ize's
 * conservative slab test ("Robust BVH Ray Traversal", JCGT 2013) and
 * geom_ray_triangle's watertight test: a ray through a shared edge or vertex
 * of a closed mesh hits exactly once. prim = face index of the mesh. ns:
 * the mesh's VERTEX "normal" channel interpolated, if it has one, else ng.
 * The positions and faces are copied when added; m is not kept.
 */
GEOM_API geom_status geom_ray_scene_add_mesh(geom_ray_scene *s, const geom_mesh *m, uint32_t *id);
/** As add_mesh from arrays: positions 3*nv doubles, tris 3*nt indices < nv
 *  (copied). normals: NULL or 3*nv doubles (copied) for ns. */
GEOM_API geom_status geom_ray_scene_add_triangles(geom_ray_scene *s, const double *positions,
                                                  size_t nv, const uint32_t *tris, size_t nt,
                                                  const double *normals, uint32_t *id);
/**
 * A B-spline or NURBS surface (deep-copied, validated), intersected
 * directly: the surface is split into rational Bezier patches at build
 * time; a query projects each patch's homogeneous control points onto two
 * planes containing the ray (Kajiya 1982, Nishita, Sederberg and Kakimoto
 * 1990), subdivides the 2D patch while its control polygon's bounding box
 * contains the origin (convex hull property: no root region is ever
 * discarded), and polishes every candidate by Newton's method on
 * S(u, v) - (o + t d) with the surface's exact derivatives to full double
 * precision; candidates are merged when their (u, v) agree within tol.
 * A sub-patch is split where its projected net varies most (so poles and
 * collapsed edges do not multiply sub-patches); a Newton root is accepted
 * when its residual |S - (o + t d)| is below 1e-9 of the control points'
 * extent plus 256 ulp of the coordinates' magnitude. Every root in the
 * domain is found, grazing and silhouette rays included: a region whose
 * projected net shrinks below 1e-10 of the extent (or 1e-12 of the domain)
 * without a Newton root is a tangency or a singular point (a pole) and
 * gives its centre, with t_error at least 1e-6 of the extent. Hits with the
 * same t (within the same tolerance) are one hit (seams, shared patch
 * edges). (u, v): the surface's parameters, to the Newton tolerance. ng:
 * the unit S_u x S_v (geom_surface_normal, defined at poles). Not closed in
 * general. Validated against SISL's s1856.
 */
GEOM_API geom_status geom_ray_scene_add_surface(geom_ray_scene *s, const geom_nurbs_surface *surf,
                                                uint32_t *id, geom_diag *diag);
/**
 * Subdivision surface (Catmull-Clark, Loop, ... with the mesh's creases as
 * in the subdivision module): hits on the limit surface, approximated by
 * refining `levels` times (0 = 5) and moving the vertices onto the limit
 * (geom_subdiv_mesh with GEOM_SUBDIV_LIMIT | GEOM_SUBDIV_NORMALS), traced
 * as a watertight mesh; ns is the interpolated limit normal. The traced
 * surface interpolates limit points linearly: its distance to the limit
 * surface is O(h^2); geom_ray_scene_object_error reports, as an estimate
 * (GEOM_ERROR_ESTIMATE), the largest distance of the level's control
 * points to their limit positions, which is of the same order.
 * prim: face of the refined mesh. scheme: geom_subdiv_scheme value.
 */
GEOM_API geom_status geom_ray_scene_add_subdiv(geom_ray_scene *s, const geom_mesh *m, int scheme,
                                               int levels, uint32_t *id, geom_diag *diag);
/**
 * Implicit surface f(x) = 0 of a compiled expression (borrowed: must outlive
 * the scene), inside f < 0, restricted to the box bounds (6 doubles). First
 * hit guaranteed by interval arithmetic (geom_implicit_expr_eval_interval
 * over the box enclosing each ray segment: a segment whose interval
 * excludes 0 is discarded, others are split, near half first, down to
 * 1e-10 of the box diagonal), then bisection on a sign change to full
 * precision (t_error = the final bracket width). A segment of that size
 * with 0 in its interval but no sign change at its ends (a tangency, or two
 * roots closer than the tolerance) gives no hit. lipschitz > 0 (0: none)
 * enables sphere tracing (steps of 0.999 |f|/L while f > 0) for closest and
 * any queries, then the interval method from where it stopped: only use a
 * true bound L >= |grad f|.
 */
GEOM_API geom_status geom_ray_scene_add_implicit(geom_ray_scene *s, const geom_implicit_expr *e,
                                                 const double bounds[6], double lipschitz,
                                                 uint32_t *id);
/**
 * Iso-surface f = iso of a sampled volume's trilinear interpolant (volume
 * borrowed), inside f < iso (as geom_ray_scene_add_volume_opt with
 * inside below). Cells are walked with the 3D-DDA of Amanatides
 * and Woo (1987); in each cell the interpolant along the ray is a cubic in
 * t, whose roots in the cell's t-range are found exactly
 * (geom_ray_poly_roots). ng: the interpolant's gradient direction. prim:
 * linear cell index.
 */
GEOM_API geom_status geom_ray_scene_add_volume(geom_ray_scene *s, const geom_implicit_volume *v,
                                               double iso, uint32_t *id);

/** Options of geom_ray_scene_add_volume_opt; zero-initialised = defaults. */
typedef struct geom_ray_volume_options {
    /** Which side of iso is inside: 0 (the default) f < iso, the normal
     *  along the gradient; 1 f > iso (a CT volume, dense inside), the
     *  normal against the gradient. The values of iso.h's
     *  GEOM_ISO_INSIDE_BELOW / GEOM_ISO_INSIDE_ABOVE;
     *  geom_implicit_volume_detect_inside finds it from the volume. */
    int inside;
} geom_ray_volume_options;

/**
 * As geom_ray_scene_add_volume with options (NULL: defaults): the same
 * roots, ng the outward normal (away from the inside: -gradient when
 * inside is 1), so `enter` (d.ng < 0) and CSG intervals follow the chosen
 * inside. GEOM_ERR_INVALID_ARG for NULL s or v, a non-finite iso or an
 * inside other than 0 or 1; GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_ray_scene_add_volume_opt(geom_ray_scene *s, const geom_implicit_volume *v,
                                                   double iso, const geom_ray_volume_options *opt,
                                                   uint32_t *id);
/** CSG node over two closed children (ids), which stop being top-level
 *  objects. Hits: the boundary points of the combined intervals (Roth 1982)
 *  with their children's data; the second child's normals are reversed in
 *  a difference. prim: the child's prim; the child (0/1) is not reported. */
GEOM_API geom_status geom_ray_scene_add_csg(geom_ray_scene *s, geom_ray_csg_op op, uint32_t a,
                                            uint32_t b, uint32_t *id);
/** Group of n >= 1 nodes (ids, copied) answered as one object (e.g. the
 *  surfaces of one file); the members stop being top-level objects. Hits
 *  keep their members' prim; closed only if its members are disjoint. */
GEOM_API geom_status geom_ray_scene_add_group(geom_ray_scene *s, const uint32_t *ids, size_t n,
                                              uint32_t *id);
/** Instance of node `of` under the affine matrix m (column-major 16
 *  doubles, object to world, applied after of's own transform). Any depth
 *  of nesting; `of` stays a top-level object if it was one. */
GEOM_API geom_status geom_ray_scene_add_instance(geom_ray_scene *s, uint32_t of, const double m[16],
                                                 uint32_t *id);
/** Give node id the affine object-to-parent matrix m (16 doubles,
 *  column-major; replaces any earlier one). Rays are mapped by the inverse,
 *  normals by the inverse transpose. GEOM_ERR_DEGENERATE for a singular m,
 *  GEOM_ERR_INVALID_ARG for a projective last row, NaN or a bad id. */
GEOM_API geom_status geom_ray_scene_set_transform(geom_ray_scene *s, uint32_t id, const double m[16]);
/** Name node id (up to 63 bytes kept). */
GEOM_API geom_status geom_ray_scene_set_name(geom_ray_scene *s, uint32_t id, const char *name);
/** Id of the node with this name, GEOM_INVALID_INDEX if none. */
GEOM_API uint32_t geom_ray_scene_find(const geom_ray_scene *s, const char *name);
/** The top-level objects, in order (hit.object indexes this list). If never
 *  called, every node not used as a CSG child, in id order. */
GEOM_API geom_status geom_ray_scene_set_objects(geom_ray_scene *s, const uint32_t *ids, size_t n);
/** Number of nodes / of top-level objects (after build). */
GEOM_API size_t geom_ray_scene_node_count(const geom_ray_scene *s);
GEOM_API size_t geom_ray_scene_object_count(const geom_ray_scene *s);
/** Node id of top-level object i (after build), GEOM_INVALID_INDEX if out of range. */
GEOM_API uint32_t geom_ray_scene_object_node(const geom_ray_scene *s, size_t i);
/** Kind of node id (0 if out of range). */
GEOM_API geom_ray_kind geom_ray_scene_node_kind(const geom_ray_scene *s, uint32_t id);

/** Build options; zero-initialised = defaults. */
typedef struct geom_ray_build_options {
    int bvh_method;     /**< geom_bvh_method for meshes (0 = SAH) */
    int bvh_threads;    /**< BVH build threads (0 = all) */
} geom_ray_build_options;

/** What a build made. */
typedef struct geom_ray_build_info {
    size_t meshes;          /**< mesh/subdivision BVHs built */
    size_t triangles;       /**< triangles in them */
    size_t bvh_nodes;       /**< nodes in them */
    size_t bvh_bytes;       /**< memory of the BVHs */
    size_t bezier_patches;  /**< Bezier patches of the surfaces */
    size_t analytic;        /**< analytic objects (no acceleration needed) */
} geom_ray_build_info;

/** Prepare the scene for queries: inverse transforms, bounds, acceleration
 *  structures. info and opt may be NULL. Statuses: GEOM_ERR_INVALID_ARG
 *  (instance or CSG cycles, a CSG child that is not closed: plane, disk,
 *  triangle, polygon, uncapped clipped quadric, open mesh or surface are
 *  allowed but give undefined intervals), GEOM_ERR_NOMEM, and the BVH's. */
GEOM_API geom_status geom_ray_scene_build(geom_ray_scene *s, const geom_ray_build_options *opt,
                                          geom_ray_build_info *info, geom_diag *diag);

/** Error report of the approximation behind node id (subdivision: limit
 *  distance, sampled), zero for exact representations. */
GEOM_API geom_status geom_ray_scene_object_error(const geom_ray_scene *s, uint32_t id,
                                                 geom_error_report *out);

/**
 * Closest hit of r in the scene: *found = 1 and *hit filled, or *found = 0.
 * GEOM_ERR_INVALID_ARG for an invalid ray (see geom_ray_check), NULL
 * arguments or an unbuilt scene (*found = 0). GEOM_ERR_NOMEM (CSG lists).
 */
GEOM_API geom_status geom_ray_scene_closest(const geom_ray_scene *s, const geom_ray *r,
                                            geom_ray_hit *hit, int *found);
/**
 * Closest hits of n rays: for each i, hits[i] and found[i] exactly as
 * geom_ray_scene_closest(s, &rays[i], &hits[i], &found[i]) gives them (bit
 * for bit), faster on many rays. When the scene is a single triangle mesh
 * (or subdivision surface) without a transform, the traversals of eight
 * rays at a time are interleaved, round robin, one node or leaf each, so
 * that the memory latency of one ray's next node overlaps the others' work
 * (Aila and Laine, "Understanding the Efficiency of Ray Traversal on GPUs",
 * HPG 2009, in software); on a CPU with AVX2, runs of eight consecutive
 * rays of one direction octant, close in origin and direction (camera rays
 * along an image row), are traced as packets instead: one traversal, each
 * child box tested against the eight rays at once (Wald et al. 2001). Any
 * other scene is queried one ray at a time.
 * rays: n rays; hits: n hits (hits[i] written only when found[i] = 1);
 * found: n ints. Every ray is answered: GEOM_ERR_INVALID_ARG when some ray
 * is invalid (see geom_ray_check; its found[i] = 0, the others answered),
 * for NULL arguments (with n > 0) or an unbuilt scene (every found[i] = 0);
 * GEOM_ERR_NOMEM (the batch's 64 KiB of traversal stacks, CSG lists).
 */
GEOM_API geom_status geom_ray_scene_closest_many(const geom_ray_scene *s, const geom_ray *rays, size_t n,
                                                 geom_ray_hit *hits, int *found);
/** Whether r hits anything in [tmin, tmax] (stops at the first hit found). */
GEOM_API geom_status geom_ray_scene_any(const geom_ray_scene *s, const geom_ray *r, int *found);
/**
 * Every hit in [tmin, tmax] sorted by t (ties: entering first), hits[0 ..
 * min(cap, *n)) written (hits may be NULL when cap is 0). *n receives the
 * total number; GEOM_ERR_LIMIT when it exceeds cap (the first cap written).
 */
GEOM_API geom_status geom_ray_scene_all(const geom_ray_scene *s, const geom_ray *r,
                                        geom_ray_hit *hits, size_t cap, size_t *n);
/**
 * Any-hit answers of n rays (shadow rays): found[i] exactly as
 * geom_ray_scene_any(s, &rays[i], &found[i]) gives it. The rays are
 * answered one after the other by the single-ray query (no per-ray setup
 * beyond it: one hit list reused by the whole batch). rays: n rays; found:
 * n ints. Every ray is answered: GEOM_ERR_INVALID_ARG when some ray is
 * invalid (see geom_ray_check; its found[i] = 0, the others answered), for
 * NULL arguments (with n > 0) or an unbuilt scene (every found[i] = 0);
 * GEOM_ERR_NOMEM (CSG lists) stops the batch. Reentrant: any number of
 * threads may call it on one scene.
 */
GEOM_API geom_status geom_ray_scene_any_many(const geom_ray_scene *s, const geom_ray *rays, size_t n,
                                             int *found);
/**
 * Every hit of each of n rays, in compressed rows (as geom_mesh_vertex_rings
 * and geom_neighbors): the hits of ray i are hits[offsets[i] ..
 * offsets[i+1]), exactly (bit for bit, same order) the *n hits
 * geom_ray_scene_all(s, &rays[i], ...) gives, sorted by t, entering first
 * on ties. rays: n rays; offsets: n + 1 size_t (offsets[0] = 0); hits: cap
 * hits (NULL allowed when cap is 0). *count receives the total,
 * offsets[n]. The caller sizes hits: with cap < *count the status is
 * GEOM_ERR_LIMIT, offsets and *count are still complete and hits[0 .. cap)
 * holds the first cap hits (rows i with offsets[i+1] <= cap are whole), so
 * the caller can call again with room for *count, or resume at the first
 * incomplete row. An invalid ray (see geom_ray_check) has an empty row;
 * the status is then GEOM_ERR_INVALID_ARG (unless GEOM_ERR_LIMIT), the
 * other rays answered; tmin > tmax gives an empty row. GEOM_ERR_INVALID_ARG
 * for NULL s, offsets or count, NULL rays with n > 0, NULL hits with
 * cap > 0, or an unbuilt scene (every row empty when offsets is given).
 * GEOM_ERR_NOMEM (hit lists) stops the batch (offsets and *count then
 * undefined). Each ray is answered by the single-ray query, one hit list
 * reused by the whole batch. Reentrant.
 */
GEOM_API geom_status geom_ray_scene_all_many(const geom_ray_scene *s, const geom_ray *rays, size_t n,
                                             size_t *offsets, geom_ray_hit *hits, size_t cap,
                                             size_t *count);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_RAY_H */
