/*
 * libgeom subdiv: subdivision surfaces by split and average.
 *
 * Schemes: Catmull-Clark (polygons of any size), Loop (triangles) and
 * bilinear, with the rules and options of OpenSubdiv 3 (Sdc): vertex
 * boundary interpolation, infinitely sharp and semi-sharp creases with
 * uniform or Chaikin decay, corners (vertex sharpness), holes, face-varying
 * boundary interpolation and the Catmull-Clark "smooth triangle" option;
 * and two schemes beyond OpenSubdiv: the interpolating modified butterfly
 * (Zorin, Schroeder and Sweldens 1996) and sqrt(3) subdivision (Kobbelt
 * 2000).
 *
 * As in OpenSubdiv, topology and data are refined separately (its Far
 * TopologyRefiner / PrimvarRefiner split):
 *
 *   geom_subdiv_refiner *r;
 *   geom_subdiv_refiner_create(mesh, &opt, &r, &diag);    // level 0 + rules
 *   geom_subdiv_refiner_refine(r, 3);                      // topology only
 *   for (int l = 1; l <= 3; l++)                            // any channels
 *       geom_subdiv_interpolate(r, l, 3, pos[l-1], pos[l]);
 *   geom_subdiv_limit(r, 3, pos[3], limit, NULL, NULL);
 *
 * The refiner holds, per level, the full topology (face-vertices,
 * face-edges, edge-vertices, edge-faces, vertex-faces, vertex-edges), the
 * subdivided sharpness of every edge and vertex and the subdivision rule of
 * every vertex (smooth, dart, crease, corner), so interpolating a channel
 * only applies the weights. geom_subdiv_mesh() does everything at once on a
 * geom_mesh: positions and every VERTEX channel with the vertex rules,
 * CORNER channels (UVs) with the face-varying rules, FACE channels copied.
 *
 * Ordering (identical to OpenSubdiv Far with
 * UniformOptions::orderVerticesFromFacesFirst = true, so results can be
 * compared by index): the vertices of level l+1 are the face points (one per
 * face of level l, in face order; none for Loop and butterfly), then the
 * edge points (one per edge, in edge order; none for sqrt3), then the
 * vertex points (one per vertex). Edges of level 0 are numbered as OpenSubdiv numbers them (in the
 * order faces first use them); child faces of face f are consecutive, one
 * per corner (quad split) or four (triangle split: the three corner
 * triangles, then the middle one). Sharpness values are single precision
 * and are subdivided exactly as OpenSubdiv does.
 *
 * Accuracy: refined values are affine combinations of their parents with
 * the scheme's weights in double precision, summed in OpenSubdiv's order;
 * they agree with OpenSubdiv's PrimvarRefinerReal<double> to a few ulp
 * (tests/validate requires 1e-12 on OpenSubdiv's 122 regression shapes at
 * levels 1-3 for positions, limits, tangents and UVs; today they agree to
 * the last bit).
 *
 * The two extra schemes work on triangles and ignore sharpness tags:
 *  - modified butterfly: Loop's 1-to-4 split; vertices stay; an edge point
 *    is the 8-point butterfly (1/2, 1/2, 1/8, 1/8, -1/16 x 4) between two
 *    regular interior vertices, Zorin's valence-k stencil of an
 *    extraordinary interior end (3/4 for it, s_j = (1/4 + cos(2 pi j/k) +
 *    cos(4 pi j/k)/2)/k on its ring; k = 3: 5/12, -1/12, -1/12; k = 4: 3/8,
 *    0, -1/8, 0), the mean of both stencils when both ends are
 *    extraordinary; boundary edges use the 4-point rule (-1/16, 9/16, 9/16,
 *    -1/16); an interior edge with one boundary end the stencil of its
 *    interior end; one joining two boundary vertices (3/8, 3/8, 1/8, 1/8);
 *  - sqrt(3): a vertex at each triangle's centroid, interior edges flipped
 *    to join the centroids, interior vertices relaxed to (1 - a_n) p + a_n
 *    mean(neighbours) with a_n = (4 - 2 cos(2 pi/n))/9; boundary and
 *    non-manifold edges are not flipped and their vertices stay (a
 *    simplification of Kobbelt's boundary rule), so faces grow 3 times per
 *    level everywhere;
 *  - face-varying data is interpolated linearly (midpoints, centroids);
 *    sqrt(3)'s flipped triangles take the values at the edge's ends from
 *    the edge's first face, so across a UV seam they mix two charts.
 *
 * Non-manifold input (edges with more than two faces, vertices with several
 * fans, faces using a vertex twice) refines as OpenSubdiv refines it: such
 * edges and vertices are made infinitely sharp. A geom_mesh built from a
 * polygon soup refines as that soup: vertices that geom_mesh_build split
 * are merged back through geom_mesh_vertex_origin().
 *
 * Thread safety: a refiner is read-only after refinement; the interpolation
 * and limit functions may run concurrently on one refiner.
 */
#ifndef GEOM_SUBDIV_H
#define GEOM_SUBDIV_H

#include "geom/core.h"
#include "geom/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* --------------------------------------------------------------- options */

typedef enum geom_subdiv_scheme {
    GEOM_SUBDIV_CATMULL_CLARK = 0, /**< Catmull & Clark 1978, any polygons (default) */
    GEOM_SUBDIV_LOOP = 1,          /**< Loop 1987, triangles only */
    GEOM_SUBDIV_BILINEAR = 2,      /**< midpoint split, quads out; no smoothing */
    GEOM_SUBDIV_BUTTERFLY = 3,     /**< modified butterfly (Zorin et al. 1996), triangles */
    GEOM_SUBDIV_SQRT3 = 4          /**< sqrt(3) subdivision (Kobbelt 2000), triangles */
} geom_subdiv_scheme;

/** Vertex boundary interpolation (OpenSubdiv VtxBoundaryInterpolation). */
typedef enum geom_subdiv_boundary {
    GEOM_SUBDIV_BOUNDARY_DEFAULT = 0,    /**< from the mesh's tag, else EDGE_ONLY */
    GEOM_SUBDIV_BOUNDARY_NONE = 1,       /**< boundary faces become holes (not output) */
    GEOM_SUBDIV_BOUNDARY_EDGE_ONLY = 2,  /**< boundary edges sharp, corners smooth */
    GEOM_SUBDIV_BOUNDARY_EDGE_AND_CORNER = 3 /**< boundary edges and corners sharp */
} geom_subdiv_boundary;

/** Face-varying boundary interpolation (OpenSubdiv FVarLinearInterpolation). */
typedef enum geom_subdiv_fvar {
    GEOM_SUBDIV_FVAR_DEFAULT = 0,       /**< from the mesh's tag, else ALL */
    GEOM_SUBDIV_FVAR_NONE = 1,          /**< smooth everywhere, boundaries as creases */
    GEOM_SUBDIV_FVAR_CORNERS_ONLY = 2,  /**< sharpen corners only */
    GEOM_SUBDIV_FVAR_CORNERS_PLUS1 = 3, /**< also junctions of 3+ regions */
    GEOM_SUBDIV_FVAR_CORNERS_PLUS2 = 4, /**< also darts and dependent corners */
    GEOM_SUBDIV_FVAR_BOUNDARIES = 5,    /**< linear along all boundaries */
    GEOM_SUBDIV_FVAR_ALL = 6            /**< linear (bilinear) everywhere */
} geom_subdiv_fvar;

typedef enum geom_subdiv_crease {
    GEOM_SUBDIV_CREASE_DEFAULT = 0, /**< from the mesh's tag, else UNIFORM */
    GEOM_SUBDIV_CREASE_UNIFORM = 1, /**< sharpness decreases by 1 per level */
    GEOM_SUBDIV_CREASE_CHAIKIN = 2  /**< Chaikin: 3/4 own + 1/4 neighbours' mean, minus 1 */
} geom_subdiv_crease;

typedef enum geom_subdiv_triangles {
    GEOM_SUBDIV_TRIANGLES_DEFAULT = 0, /**< from the mesh's tag, else CATMARK */
    GEOM_SUBDIV_TRIANGLES_CATMARK = 1, /**< Catmull-Clark weights on triangles */
    GEOM_SUBDIV_TRIANGLES_SMOOTH = 2   /**< "smooth triangle" edge weights (Catmull-Clark only) */
} geom_subdiv_triangles;

/**
 * Options; valid when zero-initialised (Catmull-Clark with OpenSubdiv's
 * regression-harness defaults: boundary edge only, uniform creasing,
 * Catmull-Clark triangles, linear face-varying interpolation), and then the
 * mesh's tags (geom_mesh_tag, read from OBJ `t` lines) take effect:
 *   crease  2k/1/0 or 2k/k/0  v0 v1 ... s      edge sharpness (vertex pairs)
 *   corner  k/1/0 or k/k/0    v ... s          vertex sharpness
 *   hole    k/0/0             f ...            faces not output
 *   interpolateboundary 1/0/0 n                0 none, 1 edge and corner, 2 edge only
 *   facevaryinginterpolateboundary 1/0/0 n     0 none, 1 corners only, 2 corners
 *                                              plus1, 3 corners plus2, 4 boundaries,
 *                                              5 all
 *   facevaryingpropagatecorners 1/0/0 n        n != 0 turns "corners plus1" into
 *                                              "corners plus2"
 *   creasemethod 0/0/1 normal|chaikin
 *   smoothtriangles 0/0/1 catmark|smooth
 * A nonzero option overrides the tag. Sharpness values are clamped to >= 0;
 * 10 or more is infinitely sharp. Tags naming missing vertices, edges or
 * faces are GEOM_ERR_INVALID_ARG; unknown tags (and OpenSubdiv 2's
 * hierarchical edits vertexedit/edgeedit/faceedit) are ignored.
 * The crease/corner/hole arrays add to the tags (applied after them, so they
 * win for the same edge or vertex); indices are level-0 vertex/face indices.
 */
typedef struct geom_subdiv_options {
    geom_subdiv_scheme scheme;
    geom_subdiv_boundary boundary;
    geom_subdiv_fvar fvar_boundary;
    geom_subdiv_crease crease_method;
    geom_subdiv_triangles triangles;
    int ignore_tags;                /**< nonzero: do not read the mesh's tags */
    size_t n_creases;               /**< edges given by crease_verts (2 per edge) */
    const uint32_t *crease_verts;
    const double *crease_sharpness; /**< n_creases values */
    size_t n_corners;
    const uint32_t *corner_verts;
    const double *corner_sharpness; /**< n_corners values */
    size_t n_holes;
    const uint32_t *hole_faces;
    /** Nonzero: the deepest level keeps only what interpolation into it
     *  needs (face-vertices, face-edges, edge-vertices, sharpness, rules),
     *  as OpenSubdiv's UniformOptions::fullTopologyInLastLevel = false;
     *  faster, but geom_subdiv_limit* then return GEOM_ERR_INVALID_ARG until
     *  a further refinement completes it. 2: also what geom_subdiv_limit
     *  and geom_subdiv_limit_normals read (vertex-edges, and vertex-faces
     *  for Catmull-Clark and bilinear), not edge-faces: those two then
     *  work (geom_subdiv_limit_fvar does not). Ignored when face-varying
     *  channels are present or for butterfly (they need the full
     *  topology). */
    int partial_last_level;
    const geom_allocator *alloc;    /**< NULL: libc */
} geom_subdiv_options;

/** Parse a scheme name ("catmull-clark" or "catmark", "loop", "bilinear",
 *  "butterfly", "sqrt3"); GEOM_ERR_INVALID_ARG for anything else. */
GEOM_API geom_status geom_subdiv_scheme_from_name(const char *name, geom_subdiv_scheme *out);
/** Lower-case name of a scheme ("catmull-clark", ...; "unknown" otherwise). */
GEOM_API const char *geom_subdiv_scheme_name(geom_subdiv_scheme s);

/* --------------------------------------------------------------- refiner */

typedef struct geom_subdiv_refiner geom_subdiv_refiner;

/**
 * A refiner over the live faces of m (deleted faces are skipped; vertex
 * indices are m's, merged through geom_mesh_vertex_origin() when m was
 * built from a soup, so level 0 has that soup's vertices). Reads the mesh's
 * tags unless opt->ignore_tags. Also records every CORNER channel of m as a
 * face-varying channel (in channel order; channels whose corners are not
 * all assigned are skipped). opt may be NULL (defaults).
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL argument, a mesh without
 * faces, Loop/butterfly/sqrt3 with a non-triangle face, a bad tag or option
 * index: diag says which); GEOM_ERR_LIMIT (a vertex with more than 65535
 * edges or faces); GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_subdiv_refiner_create(const geom_mesh *m, const geom_subdiv_options *opt,
                                       geom_subdiv_refiner **out, geom_diag *diag);

/**
 * A refiner over a polygon soup: nverts vertices, nfaces faces of sizes
 * face_sizes[i] >= 3 whose vertex indices follow one another in `indices`.
 * Faces may use a vertex twice and edges may have any number of faces
 * (non-manifold topology as OpenSubdiv accepts it). Sharp features come from
 * the option arrays only. Statuses as geom_subdiv_refiner_create.
 */
GEOM_API geom_status geom_subdiv_refiner_create_soup(size_t nverts, size_t nfaces,
                                            const uint32_t *face_sizes, const uint32_t *indices,
                                            const geom_subdiv_options *opt,
                                            geom_subdiv_refiner **out, geom_diag *diag);

/** Free a refiner. NULL is a no-op. */
GEOM_API void geom_subdiv_refiner_destroy(geom_subdiv_refiner *r);

/**
 * Add a face-varying channel (before refining): n_values values and, for
 * each face-vertex of level 0 in face order, its value index
 * (face_values has as many entries as level 0 has face-vertices).
 * *channel receives the channel index. GEOM_ERR_INVALID_ARG for an index
 * >= n_values or after geom_subdiv_refiner_refine; GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_subdiv_refiner_add_fvar(geom_subdiv_refiner *r, size_t n_values,
                                         const uint32_t *face_values, uint32_t *channel);

/** Number of face-varying channels. */
GEOM_API size_t geom_subdiv_refiner_fvar_count(const geom_subdiv_refiner *r);
/** For a refiner made from a mesh: the mesh CORNER channel id that
 *  face-varying channel `channel` was made from; GEOM_INVALID_INDEX for
 *  channels added with geom_subdiv_refiner_add_fvar or out of range. */
GEOM_API uint32_t geom_subdiv_refiner_fvar_mesh_channel(const geom_subdiv_refiner *r, uint32_t channel);

/**
 * Refine uniformly `levels` more times (topology, sharpness and rules of
 * each new level; no data). levels >= 0. Statuses: GEOM_ERR_LIMIT when the
 * total would exceed GEOM_SUBDIV_MAX_LEVEL or a level would have more than
 * 2^28 vertices, edges or face-vertices (checked before anything is
 * allocated; nothing is added); GEOM_ERR_NOMEM (the levels made before the
 * failure are kept); GEOM_ERR_INVALID_ARG for NULL r or levels < 0.
 */
#define GEOM_SUBDIV_MAX_LEVEL 12
GEOM_API geom_status geom_subdiv_refiner_refine(geom_subdiv_refiner *r, int levels);

/** Deepest level refined so far (0 before refining). */
GEOM_API int geom_subdiv_refiner_max_level(const geom_subdiv_refiner *r);
/** The refiner's scheme and effective options (after tags). */
GEOM_API geom_subdiv_scheme geom_subdiv_refiner_scheme(const geom_subdiv_refiner *r);
GEOM_API geom_subdiv_options geom_subdiv_refiner_options(const geom_subdiv_refiner *r);

typedef struct geom_subdiv_level_info {
    size_t vertices, edges, faces;
    size_t face_vertices;   /**< sum of face sizes */
    size_t max_valence;     /**< most edges or faces at one vertex */
    size_t sharp_edges;     /**< edges with sharpness > 0 (boundaries included) */
    size_t hole_faces;
} geom_subdiv_level_info;

/** Sizes of level `level` (0..max_level). GEOM_ERR_INVALID_ARG otherwise. */
GEOM_API geom_status geom_subdiv_refiner_level_info(const geom_subdiv_refiner *r, int level,
                                           geom_subdiv_level_info *info);

/**
 * The faces of a level as a soup: face_sizes (faces entries) and indices
 * (face_vertices entries); either may be NULL. Hole faces are included;
 * is_hole (faces bytes, may be NULL) flags them.
 */
GEOM_API geom_status geom_subdiv_refiner_faces(const geom_subdiv_refiner *r, int level,
                                      uint32_t *face_sizes, uint32_t *indices, uint8_t *is_hole);

/** The face-vertex indices of level `level` (face_vertices entries, faces in
 *  order: what geom_subdiv_refiner_faces copies into `indices`), without a
 *  copy: valid until r is refined again or destroyed. NULL for a NULL r or
 *  a level out of 0..max_level. */
GEOM_API const uint32_t *geom_subdiv_refiner_face_indices(const geom_subdiv_refiner *r,
                                                          int level);

/** Edge vertices of a level: 2 per edge (edges entries * 2), and optionally
 *  each edge's sharpness (edges floats; 10 = infinite). */
GEOM_API geom_status geom_subdiv_refiner_edges(const geom_subdiv_refiner *r, int level, uint32_t *verts,
                                      float *sharpness);

/** Vertex sharpness of a level (vertices floats) and the rule of each vertex
 *  (vertices bytes: 1 smooth, 2 dart, 4 crease, 8 corner); either may be NULL. */
GEOM_API geom_status geom_subdiv_refiner_vertex_rules(const geom_subdiv_refiner *r, int level,
                                             float *sharpness, uint8_t *rule);

/** What a child vertex comes from. */
typedef enum geom_subdiv_origin {
    GEOM_SUBDIV_FROM_FACE = 0,
    GEOM_SUBDIV_FROM_EDGE = 1,
    GEOM_SUBDIV_FROM_VERTEX = 2
} geom_subdiv_origin;

/**
 * Parent-to-child map: the vertex of level `level`+1 made from face, edge or
 * vertex `index` of level `level` (0 <= level < max_level).
 * GEOM_INVALID_INDEX when there is none (face points of Loop, butterfly and
 * sqrt3's edges) or the arguments are out of range.
 */
GEOM_API uint32_t geom_subdiv_refiner_child_vertex(const geom_subdiv_refiner *r, int level,
                                          geom_subdiv_origin kind, uint32_t index);
/** Child-to-parent map: what vertex v of level `level` (>= 1) comes from.
 *  GEOM_ERR_INVALID_ARG for out-of-range arguments. */
GEOM_API geom_status geom_subdiv_refiner_vertex_parent(const geom_subdiv_refiner *r, int level, uint32_t v,
                                              geom_subdiv_origin *kind, uint32_t *parent);
/** The parent face (of level `level`-1) of face f of level `level` >= 1,
 *  GEOM_INVALID_INDEX when out of range. */
GEOM_API uint32_t geom_subdiv_refiner_face_parent(const geom_subdiv_refiner *r, int level, uint32_t f);

/* ------------------------------------------------------- data refinement */

/**
 * Interpolate vertex data from level `level`-1 to level `level` (1 ..
 * max_level) with the scheme's vertex rules (OpenSubdiv
 * PrimvarRefiner::Interpolate for Catmull-Clark, Loop and bilinear; the
 * stencils described at the top for butterfly and sqrt3): src has ncomp
 * doubles per vertex of level-1, dst receives ncomp per vertex of level
 * (src and dst must not overlap). ncomp >= 1. GEOM_ERR_INVALID_ARG
 * otherwise; GEOM_ERR_NOMEM (scratch of a few kB).
 */
GEOM_API geom_status geom_subdiv_interpolate(const geom_subdiv_refiner *r, int level, size_t ncomp,
                                    const double *src, double *dst);

/**
 * Varying interpolation (OpenSubdiv InterpolateVarying): linear averages
 * whatever the scheme (face point = mean of the face, edge point = midpoint,
 * vertex point = the vertex). Same arguments as geom_subdiv_interpolate.
 */
GEOM_API geom_status geom_subdiv_interpolate_varying(const geom_subdiv_refiner *r, int level, size_t ncomp,
                                            const double *src, double *dst);

/** Face data: each face of `level` gets the value of its parent face
 *  (ncomp doubles per face). */
GEOM_API geom_status geom_subdiv_interpolate_face(const geom_subdiv_refiner *r, int level, size_t ncomp,
                                         const double *src, double *dst);

/** Number of values of face-varying channel `channel` at `level` (0 if out
 *  of range). At level 0 it is the n_values given to add_fvar. */
GEOM_API size_t geom_subdiv_fvar_size(const geom_subdiv_refiner *r, uint32_t channel, int level);

/** The value index of every face-vertex of `level` (face_vertices entries)
 *  for face-varying channel `channel`. */
GEOM_API geom_status geom_subdiv_fvar_face_values(const geom_subdiv_refiner *r, uint32_t channel, int level,
                                         uint32_t *face_values);

/**
 * Interpolate face-varying data of `channel` from level-1 to level with the
 * face-varying rules (the fvar_boundary option; OpenSubdiv
 * InterpolateFaceVarying; linear for bilinear, butterfly and sqrt3): src
 * has ncomp doubles per value of level-1 (geom_subdiv_fvar_size), dst per
 * value of level. GEOM_ERR_INVALID_ARG for bad arguments, GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_subdiv_interpolate_fvar(const geom_subdiv_refiner *r, uint32_t channel,
                                         int level, size_t ncomp, const double *src,
                                         double *dst);

/* ----------------------------------------------------------------- limit */

/**
 * Limit positions (and optionally the two limit tangents) of the vertices of
 * the deepest level, from its data src (ncomp doubles per vertex), with the
 * limit masks of OpenSubdiv's Sdc schemes (PrimvarRefiner::Limit):
 *  - Catmull-Clark smooth and dart vertices of valence n: the eigenvector
 *    mask (n^2 v + 4 sum(edge neighbours) + sum(diagonal neighbours)) /
 *    (n (n + 5)) (Halstead, Kass and DeRose 1993), which assumes quads
 *    around the vertex (true after one level);
 *  - Loop smooth vertices: (1 - n e) v + e sum(neighbours), e = 1 / (n +
 *    3 / (8 g)), g = (5/8 - (3/8 + cos(2 pi/n)/4)^2) / n;
 *  - crease and boundary vertices: the cubic B-spline mask 1/6, 2/3, 1/6
 *    along the crease; corners stay;
 *  - bilinear and butterfly: the vertex itself; sqrt3: (p + 3 a_n q) /
 *    (1 + 3 a_n), q the mean of the n neighbours, a_n = (4 - 2 cos(2 pi/n))
 *    / 9 (the fixed point of Kobbelt's relaxation); boundary vertices stay.
 * Semi-sharp features that have not decayed use the vertex's current rule
 * (refine until they decay for the true limit). tan1/tan2 (both or
 * neither, may be NULL) receive tangents (not normalised) along the
 * vertex's first edge and across, so that tan1 x tan2 is the outward normal
 * of counter-clockwise faces; zero for isolated vertices, butterfly and
 * sqrt3. Accuracy: the masks' values in double arithmetic (a few ulp).
 * GEOM_ERR_INVALID_ARG for NULL arguments, ncomp 0, or a deepest level
 * made with partial_last_level; GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_subdiv_limit(const geom_subdiv_refiner *r, size_t ncomp, const double *src,
                              double *pos, double *tan1, double *tan2);

/**
 * Unit limit normals (3 doubles per vertex of the deepest level) from the
 * limit tangents of geom_subdiv_limit for positions src (3 per vertex);
 * Catmull-Clark, Loop and bilinear. A vertex whose tangents are parallel or
 * zero gets (0,0,0) and is counted in *n_degenerate (may be NULL).
 * GEOM_ERR_INVALID_ARG for butterfly and sqrt3.
 */
GEOM_API geom_status geom_subdiv_limit_normals(const geom_subdiv_refiner *r, const double *src,
                                      double *normals, size_t *n_degenerate);

/** Limit of face-varying data at the deepest level (OpenSubdiv
 *  LimitFaceVarying): per value of the channel at that level (ncomp
 *  doubles each); values stay where linear (option "all", bilinear,
 *  butterfly, sqrt3). GEOM_ERR_INVALID_ARG, GEOM_ERR_NOMEM. */
GEOM_API geom_status geom_subdiv_limit_fvar(const geom_subdiv_refiner *r, uint32_t channel, size_t ncomp,
                                   const double *src, double *dst);

/* ------------------------------------------------------- whole-mesh call */

/** Flags for geom_subdiv_mesh. */
#define GEOM_SUBDIV_LIMIT 1u   /**< move the final positions to the limit surface */
#define GEOM_SUBDIV_NORMALS 2u /**< add a VERTEX "normal" channel: limit normals (angle-weighted
                                    face normals for butterfly and sqrt3) */

/** What geom_subdiv_mesh did and the error it achieved. */
typedef struct geom_subdiv_report {
    int levels;
    size_t vertices, faces;   /**< of the output mesh */
    size_t input_faces;       /**< faces refined (level 0) */
    size_t hole_faces;        /**< output-level faces dropped as holes */
    size_t fvar_channels;     /**< CORNER channels refined */
    size_t dropped_channels;  /**< EDGE channels and unusable CORNER channels not carried */
    /** Distance from each vertex of the final refined level to its limit
     *  position (0 for butterfly, where vertices lie on the limit surface;
     *  0 when GEOM_SUBDIV_LIMIT put them there): max and root mean square,
     *  and the bounding-box diagonal of level 0 for scale. Measured at every
     *  vertex (not a bound between vertices). */
    double max_limit_distance;
    double rms_limit_distance;
    double bbox_diagonal;
    /** The report every approximating operation gives (geom/core.h): max
     *  and mean distance to the limit over the final level's vertices
     *  (method GEOM_ERROR_SAMPLED; GEOM_ERROR_BOUND with 0 when
     *  GEOM_SUBDIV_LIMIT put them there), evaluations = pieces = vertices
     *  measured, tolerance 0 (a fixed number of levels), seconds = the
     *  whole call. */
    geom_error_report error;
    /** max_limit_distance and rms_limit_distance of the final refined level
     *  before any GEOM_SUBDIV_LIMIT projection, whatever the flags: a caller
     *  that keeps the limit positions gets the refined level's error from
     *  the same call (measured at every vertex, as above). */
    double level_max_limit_distance;
    double level_rms_limit_distance;
} geom_subdiv_report;

/**
 * Subdivide m `levels` times (0..GEOM_SUBDIV_MAX_LEVEL) into a new mesh
 * *out: positions and the other VERTEX channels with the vertex rules,
 * CORNER channels with the face-varying rules (seams kept), FACE channels
 * and face groups copied from the parent face; EDGE channels are dropped.
 * Hole faces are left out. The output carries the mesh's option tags and
 * "crease"/"corner" tags for the edges and vertices still sharp (so
 * refining the output again with the same options continues the same
 * surface, except at holes and at non-manifold features that
 * geom_mesh_build splits).
 * flags: OR of GEOM_SUBDIV_LIMIT, GEOM_SUBDIV_NORMALS. Loop, butterfly and
 * sqrt3 need triangles (GEOM_ERR_INVALID_ARG otherwise; triangulate
 * first). report and diag may be NULL. Statuses as
 * geom_subdiv_refiner_create and geom_subdiv_refiner_refine, and those of
 * geom_mesh_build for the output.
 */
GEOM_API geom_status geom_subdiv_mesh(const geom_mesh *m, const geom_subdiv_options *opt, int levels,
                             unsigned flags, geom_mesh **out, geom_subdiv_report *report,
                             geom_diag *diag);

/**
 * Build the mesh of level `level` (0..max_level) of r from positions the
 * caller refined (3 per vertex of that level) and optionally normals (3 per
 * vertex, stored as the VERTEX channel "normal", replacing a CORNER
 * "normal"; NULL: none). When `like` is the mesh r was made from (or a mesh
 * with the same vertices, faces and channels), its other channels, face
 * groups, mtllibs and option tags are carried as geom_subdiv_mesh does,
 * refined here from level 0; NULL carries nothing. Hole faces are left out
 * (*hole_faces, may be NULL, receives their number) with the vertices only
 * they used. Tools use this to time the levels themselves.
 * Statuses: GEOM_OK, GEOM_ERR_INVALID_ARG, GEOM_ERR_NOMEM, and those of
 * geom_mesh_build.
 */
GEOM_API geom_status geom_subdiv_build_mesh(const geom_subdiv_refiner *r, int level, const double *positions,
                                   const double *normals, const geom_mesh *like, geom_mesh **out,
                                   size_t *hole_faces, geom_diag *diag);

/**
 * Whether the mesh geom_subdiv_build_mesh(r, level, positions, normals,
 * like, ...) would make (normals non-NULL when with_normals) is plainly the
 * level itself: all its vertices in order with their positions (and a
 * VERTEX "normal" channel when with_normals) and nothing else, and all its
 * faces in geom_subdiv_refiner_faces order, each starting at its first
 * vertex. That holds for a level >= 1 of Catmull-Clark, bilinear or Loop
 * over an oriented manifold base without isolated vertices (nothing is
 * repaired), without hole faces, creases or corners still sharp, and when
 * `like` (may be NULL) has no other channel (a "normal" one only with
 * with_normals, which replaces it), no face group, material library or
 * option tag; positions (3 per vertex) must be finite.
 * A writer can then write the level straight from its faces and positions
 * (geom_meshio_write_soup gives the same OBJ bytes geom_meshio_write gives
 * for the mesh) without building the half-edge mesh: geom-subdivide does.
 * Returns 1 when so; 0 otherwise, and for a NULL r or positions or a level
 * out of 1..max_level.
 */
GEOM_API int geom_subdiv_level_is_plain(const geom_subdiv_refiner *r, int level,
                                        const double *positions, int with_normals,
                                        const geom_mesh *like);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_SUBDIV_H */
