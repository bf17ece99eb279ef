/*
 * libgeom mesh: half-edge polygon meshes with attribute channels, building
 * from polygon soups (with repair), navigation, queries, validation,
 * triangulation, normals, tangent frames, UV data, feature edges and clipping.
 *
 * Data layout (pmp-library style, arrays):
 *  - halfedges come in pairs: opposite(h) = h ^ 1, edge(h) = h >> 1;
 *  - per halfedge: next, prev, vertex (the vertex it points TO), face
 *    (GEOM_INVALID_INDEX on a boundary halfedge);
 *  - per vertex: one outgoing halfedge, a boundary one when the vertex is on
 *    a boundary (GEOM_INVALID_INDEX for an isolated vertex);
 *  - per face: one of its halfedges;
 *  - polygons of any valence >= 3; faces are counter-clockwise seen from
 *    outside (their normal by the right-hand rule);
 *  - deletion marks elements; geom_mesh_compact() collects them, so indices
 *    stay stable until then.
 *
 * Attribute channels hold doubles, `ncomp` per value, in one of four domains:
 *  - VERTEX, FACE, EDGE: one value per element;
 *  - CORNER (face-varying): each halfedge h with a face has an index into
 *    the channel's own value pool; h stands for the corner of face(h) at
 *    vertex(h) (the vertex h points to). Two corners at one vertex with
 *    different indices form a seam (UV seams, split normals), so OBJ
 *    v/vt/vn round-trips exactly. Boundary halfedges hold GEOM_INVALID_INDEX.
 * Positions are the VERTEX channel "position" (3 components), always present
 * as channel 0. Conventional names: "normal" (3), "uv" (2), "color" (3 or 4),
 * "tangent" (4: xyz and the bitangent sign in w).
 *
 * Accuracy: topology is exact; geometric quantities use double arithmetic and
 * state their accuracy per function.
 */
#ifndef GEOM_MESH_H
#define GEOM_MESH_H

#include "geom/core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define GEOM_INVALID_INDEX UINT32_MAX

typedef struct geom_mesh geom_mesh;

/* ------------------------------------------------------------- lifetime */

/** A new empty mesh (with the "position" channel). alloc may be NULL.
 *  Returns NULL when out of memory. */
GEOM_API geom_mesh *geom_mesh_create(const geom_allocator *alloc);
/** Free a mesh and everything it owns. NULL is a no-op. */
GEOM_API void geom_mesh_destroy(geom_mesh *m);
/** Deep copy (topology, channels, tags, polylines, metadata).
 *  GEOM_ERR_NOMEM / GEOM_ERR_INVALID_ARG. */
GEOM_API geom_status geom_mesh_clone(const geom_mesh *m, geom_mesh **out);
/** Remove every element, channel (except "position"), tag and polyline. */
GEOM_API void geom_mesh_clear(geom_mesh *m);

/* --------------------------------------------------------------- counts */

/** Sizes of the element arrays, including elements marked deleted. */
GEOM_API size_t geom_mesh_n_vertices(const geom_mesh *m);
GEOM_API size_t geom_mesh_n_halfedges(const geom_mesh *m); /**< = 2 * n_edges */
GEOM_API size_t geom_mesh_n_edges(const geom_mesh *m);
GEOM_API size_t geom_mesh_n_faces(const geom_mesh *m);
/** Counts of live (not deleted) elements. */
GEOM_API size_t geom_mesh_n_live_vertices(const geom_mesh *m);
GEOM_API size_t geom_mesh_n_live_edges(const geom_mesh *m);
GEOM_API size_t geom_mesh_n_live_faces(const geom_mesh *m);

/* ----------------------------------------------------------- navigation */
/* All take valid indices (behaviour for out-of-range indices: return
 * GEOM_INVALID_INDEX / false, never read out of bounds). */

GEOM_API uint32_t geom_mesh_he_next(const geom_mesh *m, uint32_t h);
GEOM_API uint32_t geom_mesh_he_prev(const geom_mesh *m, uint32_t h);
/** h ^ 1. */
GEOM_API uint32_t geom_mesh_he_opposite(const geom_mesh *m, uint32_t h);
/** The vertex h points to. */
GEOM_API uint32_t geom_mesh_he_vertex(const geom_mesh *m, uint32_t h);
/** The vertex h starts from (= vertex of the opposite). */
GEOM_API uint32_t geom_mesh_he_from(const geom_mesh *m, uint32_t h);
/** The face of h, GEOM_INVALID_INDEX on a boundary halfedge. */
GEOM_API uint32_t geom_mesh_he_face(const geom_mesh *m, uint32_t h);
/** h >> 1. */
GEOM_API uint32_t geom_mesh_he_edge(const geom_mesh *m, uint32_t h);
/** Halfedge 0 or 1 of edge e: 2e + i. */
GEOM_API uint32_t geom_mesh_edge_he(const geom_mesh *m, uint32_t e, int i);
/** The outgoing halfedge of v (boundary one if v is on a boundary);
 *  GEOM_INVALID_INDEX for an isolated vertex. */
GEOM_API uint32_t geom_mesh_vertex_he(const geom_mesh *m, uint32_t v);
/** One halfedge of face f. */
GEOM_API uint32_t geom_mesh_face_he(const geom_mesh *m, uint32_t f);

GEOM_API bool geom_mesh_he_is_boundary(const geom_mesh *m, uint32_t h);
/** True if either halfedge of e is a boundary halfedge. */
GEOM_API bool geom_mesh_edge_is_boundary(const geom_mesh *m, uint32_t e);
/** True if v has a boundary outgoing halfedge or is isolated. */
GEOM_API bool geom_mesh_vertex_is_boundary(const geom_mesh *m, uint32_t v);
GEOM_API bool geom_mesh_vertex_is_isolated(const geom_mesh *m, uint32_t v);
/** Number of edges at v. */
GEOM_API size_t geom_mesh_vertex_valence(const geom_mesh *m, uint32_t v);
/** Number of vertices (= edges) of f. */
GEOM_API size_t geom_mesh_face_valence(const geom_mesh *m, uint32_t f);
/** The edge between a and b (either direction), or GEOM_INVALID_INDEX.
 *  Also see geom_mesh_find_halfedge. */
GEOM_API uint32_t geom_mesh_find_edge(const geom_mesh *m, uint32_t a, uint32_t b);
/** The halfedge from a to b, or GEOM_INVALID_INDEX. */
GEOM_API uint32_t geom_mesh_find_halfedge(const geom_mesh *m, uint32_t a, uint32_t b);

GEOM_API bool geom_mesh_vertex_is_deleted(const geom_mesh *m, uint32_t v);
GEOM_API bool geom_mesh_edge_is_deleted(const geom_mesh *m, uint32_t e);
GEOM_API bool geom_mesh_face_is_deleted(const geom_mesh *m, uint32_t f);

/* ---------------------------------------------------------- circulators */

typedef enum geom_mesh_circ_kind {
    GEOM_MESH_CIRC_VERTEX_OUTGOING = 0, /**< outgoing halfedges of a vertex */
    GEOM_MESH_CIRC_VERTEX_FACES = 1,    /**< faces around a vertex (boundary gaps skipped) */
    GEOM_MESH_CIRC_VERTEX_VERTICES = 2, /**< neighbouring vertices */
    GEOM_MESH_CIRC_FACE_HALFEDGES = 3,  /**< halfedges of a face, in order */
    GEOM_MESH_CIRC_FACE_VERTICES = 4    /**< vertices of a face, in order */
} geom_mesh_circ_kind;

/**
 * A circulator; a plain value, no allocation. Usage:
 *   geom_mesh_circ c = geom_mesh_circ_begin(m, GEOM_MESH_CIRC_VERTEX_FACES, v);
 *   uint32_t f;
 *   while (geom_mesh_circ_next(&c, &f)) { ... }
 * Around a vertex the order is counter-clockwise (seen from outside) and, on
 * a boundary vertex, starts at the boundary outgoing halfedge, so every
 * element is visited exactly once. An isolated or deleted vertex (face)
 * yields nothing. The mesh must not change while a circulator is in use.
 */
typedef struct geom_mesh_circ {
    const geom_mesh *mesh;
    geom_mesh_circ_kind kind;
    uint32_t start;
    uint32_t current;
    int active;
} geom_mesh_circ;

GEOM_API geom_mesh_circ geom_mesh_circ_begin(const geom_mesh *m, geom_mesh_circ_kind kind, uint32_t elem);
/** Writes the next element (halfedge, face or vertex index, by kind) and
 *  returns true, or returns false when the cycle is complete. */
GEOM_API bool geom_mesh_circ_next(geom_mesh_circ *c, uint32_t *out);

/* ---------------------------------------------------- low-level editing */

/** Append a vertex at p (3 doubles); *out receives its index (may be NULL).
 *  Other vertex channels get zeros. GEOM_ERR_NOMEM, GEOM_ERR_LIMIT
 *  (2^32-1 elements). */
GEOM_API geom_status geom_mesh_add_vertex(geom_mesh *m, const double p[3], uint32_t *out);
/**
 * Add a face over n >= 3 existing vertices (in counter-clockwise order),
 * linking halfedges as a manifold polygon mesh requires (as pmp's add_face).
 * GEOM_ERR_INVALID_ARG for out-of-range or repeated vertices or n < 3;
 * GEOM_ERR_NONMANIFOLD if the face would create a non-manifold edge or
 * vertex, or its orientation is inconsistent with its neighbours (the mesh is
 * unchanged in every error case). Corner channel indices of the new
 * halfedges are GEOM_INVALID_INDEX; set them with geom_mesh_corner_indices.
 */
GEOM_API geom_status geom_mesh_add_face(geom_mesh *m, size_t n, const uint32_t *verts, uint32_t *out);
/** Mark face f deleted, together with edges and vertices left without
 *  faces (as pmp's delete_face). */
GEOM_API geom_status geom_mesh_delete_face(geom_mesh *m, uint32_t f);
/** Mark v and its incident faces deleted. */
GEOM_API geom_status geom_mesh_delete_vertex(geom_mesh *m, uint32_t v);
/**
 * Remove every deleted element and renumber the rest (keeping relative
 * order), channels and corner pools included (unused corner values are
 * kept). If the maps are non-NULL they receive, for each old index, the new
 * index or GEOM_INVALID_INDEX (n_vertices / n_faces entries, sizes before
 * compaction).
 */
GEOM_API geom_status geom_mesh_compact(geom_mesh *m, uint32_t *vertex_map, uint32_t *face_map);

/* ---------------------------------------------------- building from soup */

/** The element kind an attribute channel's values belong to (see the
 *  module comment). */
typedef enum geom_mesh_domain {
    GEOM_MESH_DOMAIN_VERTEX = 0,
    GEOM_MESH_DOMAIN_FACE = 1,
    GEOM_MESH_DOMAIN_EDGE = 2,
    GEOM_MESH_DOMAIN_CORNER = 3
} geom_mesh_domain;


/**
 * One attribute stream for geom_mesh_build (as an OpenSubdiv FVarChannel):
 * the channel `name` in `domain` with `ncomp` doubles per value.
 *  - VERTEX: `values` holds nverts * ncomp doubles (input vertex order);
 *  - FACE: `values` holds nfaces * ncomp doubles (input face order);
 *  - CORNER: `values` is a pool of n_values values and `indices` holds one
 *    pool index per face corner, parallel to the build's `indices` (the sum
 *    of face_sizes entries; GEOM_INVALID_INDEX = no value at that corner).
 * EDGE channels are not accepted (edges do not exist before the build).
 */
typedef struct geom_mesh_build_channel {
    const char *name;
    geom_mesh_domain domain;
    size_t ncomp;           /**< >= 1 */
    size_t n_values;        /**< CORNER: pool size; ignored for VERTEX and FACE */
    const double *values;   /**< see above; may be NULL when there are no values */
    const uint32_t *indices; /**< CORNER only: one pool index per face corner */
} geom_mesh_build_channel;

typedef struct geom_mesh_build_options {
    /** Nonzero: faces with out-of-range or repeated indices (or fewer than 3)
     *  are skipped and counted instead of failing the build. */
    int skip_invalid_faces;
    /** Nonzero: do not reorient faces for consistency (a face that cannot be
     *  linked is then detached as for non-manifold edges). */
    int keep_orientation;
    /**
     * Deprecated, ignored: kept so that code setting it still compiles, and
     * to be removed in a later release. Every input is first built directly
     * (halfedges linked as the faces give them, the edge pairing and the
     * vertex fans checked on the way) and goes through the repair passes
     * only when that check fails, so input that is already a valid oriented
     * manifold (what the library's own tessellation, marching cubes,
     * subdivision and clipping produce) takes the direct path whatever this
     * field says, and the result is the repairing build's, element for
     * element. Debug builds (NDEBUG undefined) validate every directly built
     * result.
     */
    int trusted;
    /** Attribute streams attached to the result, in this order
     *  (n_channels entries; NULL when 0), each a new channel (the build
     *  replaces m's channels; "position" and two streams of one name and
     *  domain are GEOM_ERR_INVALID_ARG). Vertices that the repairing path
     *  adds take the values of their input vertex (geom_mesh_vertex_origin),
     *  faces and corners those of their input face and corner; skipped
     *  faces' values are dropped. */
    const geom_mesh_build_channel *channels;
    size_t n_channels;
} geom_mesh_build_options;

#define GEOM_MESH_REPORT_FIRST 8

/** What building from a soup changed. Every count has the first up to
 *  GEOM_MESH_REPORT_FIRST element indices (input face indices, or input
 *  vertex indices for split vertices) so a user can find them. */
typedef struct geom_mesh_build_report {
    size_t invalid_faces;          /**< skipped: out-of-range/repeated index, < 3 vertices */
    uint32_t first_invalid_faces[GEOM_MESH_REPORT_FIRST];
    size_t flipped_faces;          /**< reversed to agree with their neighbours */
    uint32_t first_flipped_faces[GEOM_MESH_REPORT_FIRST];
    size_t nonmanifold_edges;      /**< input edges used by more than two faces, or twice
                                        in the same direction after orientation */
    uint32_t first_nonmanifold_faces[GEOM_MESH_REPORT_FIRST];
    size_t detached_faces;         /**< faces given their own copies of an edge's vertices
                                        to resolve a non-manifold or non-orientable edge */
    uint32_t first_detached_faces[GEOM_MESH_REPORT_FIRST];
    size_t split_vertices;         /**< non-manifold vertices (several fans) split */
    uint32_t first_split_vertices[GEOM_MESH_REPORT_FIRST];
    size_t added_vertices;         /**< vertices created by splitting and detaching */
    size_t isolated_vertices;      /**< input vertices no face uses (kept) */
    size_t nonorientable_components; /**< components that needed a cut to orient */
} geom_mesh_build_report;

/**
 * Replace m's contents with the polygon soup: nverts points (3*nverts
 * doubles), nfaces faces whose sizes are face_sizes[i] (nfaces uint32) and
 * whose vertex indices are listed consecutively in `indices` (sum of sizes).
 * The result is a manifold, consistently oriented half-edge mesh: each
 * connected set of faces is oriented like its first face (breadth-first
 * over manifold edges); an edge used by more than two faces keeps glued the
 * pairs of its faces that already meet around both of its vertices (the faces
 * of one closed surface), then its first compatible remaining pair when that
 * joins no two vertices twice; the other faces are detached onto other copies
 * of the edge's vertices; a vertex whose faces form several fans is split into
 * one vertex per fan. No output has two edges between the same two vertices. Output vertex i < nverts corresponds to input vertex i; added
 * vertices follow, and the VERTEX-domain int map
 * geom_mesh_vertex_origin() gives the input vertex of each. Face i of the
 * output is input face i unless invalid faces were skipped (then faces keep
 * their order without the skipped ones; geom_mesh_face_origin() maps them).
 * opt->channels attach attribute streams (vertex, face and corner values)
 * in the same call. Input that needs no repair is linked directly, without
 * the repair passes (geom_mesh_build_options.trusted is ignored).
 * report and diag may be NULL; opt NULL means defaults.
 * Returns GEOM_OK (repairs are not errors: see the report),
 * GEOM_ERR_INVALID_ARG for an invalid face when skip_invalid_faces is 0 (the
 * diag names the face), non-finite coordinates, or an invalid stream (EDGE
 * domain, "position", a repeated name, ncomp 0, NULL values or indices, a
 * corner index past the pool), GEOM_ERR_NOMEM, GEOM_ERR_LIMIT.
 */
GEOM_API geom_status geom_mesh_build(geom_mesh *m, size_t nverts, const double *xyz, size_t nfaces,
                            const uint32_t *face_sizes, const uint32_t *indices,
                            const geom_mesh_build_options *opt, geom_mesh_build_report *report,
                            geom_diag *diag);

/** For each output vertex, the input vertex it came from (n_vertices
 *  entries), after geom_mesh_build; NULL if the mesh was not built from a soup. */
GEOM_API const uint32_t *geom_mesh_vertex_origin(const geom_mesh *m);
/** For each output face, the input face it came from (n_faces entries). */
GEOM_API const uint32_t *geom_mesh_face_origin(const geom_mesh *m);

/**
 * The mesh as a soup: face_sizes (n_live_faces entries) and indices
 * (sum of sizes); either may be NULL to query sizes: *n_indices receives the
 * total index count. Vertex indices are the mesh's (deleted vertices keep
 * their slots; compact first for dense output). Each face lists
 * he_vertex(h) for h = face_he(f), next(h), ... so the listed order is the
 * face's counter-clockwise order; face_he(f) is chosen by geom_mesh_build so
 * that a soup round-trips with each face starting at its first input vertex.
 */
GEOM_API geom_status geom_mesh_to_soup(const geom_mesh *m, uint32_t *face_sizes, uint32_t *indices,
                              size_t *n_indices);

/* -------------------------------------------------------------- channels */

/** Number of channels; channel ids are 0 .. count-1 (0 is "position").
 *  Removing a channel renumbers the ones after it. */
GEOM_API size_t geom_mesh_channel_count(const geom_mesh *m);
/**
 * Add a channel with `ncomp` >= 1 doubles per value, zero-filled. For CORNER
 * channels the pool starts empty and every corner index is
 * GEOM_INVALID_INDEX. *id receives the id (may be NULL).
 * GEOM_ERR_INVALID_ARG if a channel of that name already exists in that
 * domain or the name is empty or longer than 63 bytes.
 */
GEOM_API geom_status geom_mesh_channel_add(geom_mesh *m, const char *name, geom_mesh_domain domain,
                                  size_t ncomp, uint32_t *id);
/** The id of the channel `name` in `domain`, or GEOM_INVALID_INDEX. */
GEOM_API uint32_t geom_mesh_channel_find(const geom_mesh *m, const char *name, geom_mesh_domain domain);
/** Remove a channel (not channel 0). */
GEOM_API geom_status geom_mesh_channel_remove(geom_mesh *m, uint32_t id);
GEOM_API const char *geom_mesh_channel_name(const geom_mesh *m, uint32_t id);
GEOM_API geom_mesh_domain geom_mesh_channel_domain(const geom_mesh *m, uint32_t id);
GEOM_API size_t geom_mesh_channel_ncomp(const geom_mesh *m, uint32_t id);
/** Number of values: the element count for VERTEX/FACE/EDGE, the pool size
 *  for CORNER. */
GEOM_API size_t geom_mesh_channel_size(const geom_mesh *m, uint32_t id);
/** The values, size * ncomp doubles, row-major. Valid until the mesh's
 *  element counts or the pool size change. */
GEOM_API double *geom_mesh_channel_data(geom_mesh *m, uint32_t id);
GEOM_API const double *geom_mesh_channel_cdata(const geom_mesh *m, uint32_t id);
/** Resize a CORNER channel's value pool to n values (new ones zeroed). */
GEOM_API geom_status geom_mesh_corner_pool_resize(geom_mesh *m, uint32_t id, size_t n);
/** The per-halfedge pool indices of a CORNER channel (n_halfedges entries);
 *  NULL for other domains. */
GEOM_API uint32_t *geom_mesh_corner_indices(geom_mesh *m, uint32_t id);
GEOM_API const uint32_t *geom_mesh_corner_cindices(const geom_mesh *m, uint32_t id);
/** Shorthand for channel 0's data: 3*n_vertices doubles. */
GEOM_API double *geom_mesh_positions(geom_mesh *m);
GEOM_API const double *geom_mesh_cpositions(const geom_mesh *m);

/* ------------------------------------------------------ tags and metadata */

/**
 * Mesh tags, as the OBJ `t name nint/nfloat/nstring ints floats strings`
 * statements OpenSubdiv uses (crease, corner, hole, interpolateboundary,
 * facevaryingpropagatecorners, ...). Ints are vertex/face indices as in the
 * file (0-based in OpenSubdiv's convention), stored as int64.
 */
typedef struct geom_mesh_tag {
    const char *name;
    size_t nint, nfloat, nstring;
    const int64_t *ints;
    const double *floats;
    const char *const *strings;
} geom_mesh_tag;

GEOM_API size_t geom_mesh_tag_count(const geom_mesh *m);
/** View of tag i (pointers valid until the tags change). GEOM_ERR_INVALID_ARG
 *  if i is out of range. */
GEOM_API geom_status geom_mesh_tag_get(const geom_mesh *m, size_t i, geom_mesh_tag *out);
/** Append a copy of *tag. */
GEOM_API geom_status geom_mesh_tag_add(geom_mesh *m, const geom_mesh_tag *tag);

/**
 * Face groups: the OBJ `g`, `o`, `usemtl` and `s` state of each face, kept on
 * read and written back. A face's group is an index into the mesh's group
 * table (GEOM_INVALID_INDEX = none); each entry holds the four strings (NULL
 * when unset; smoothing "off" or a number as text).
 */
typedef struct geom_mesh_group {
    const char *group;    /**< g names (space-separated as in the file) */
    const char *object;   /**< o name */
    const char *material; /**< usemtl name */
    const char *smoothing; /**< s value */
} geom_mesh_group;

GEOM_API size_t geom_mesh_group_count(const geom_mesh *m);
GEOM_API geom_status geom_mesh_group_get(const geom_mesh *m, size_t i, geom_mesh_group *out);
/** Append a copy of *g; *id receives its index. */
GEOM_API geom_status geom_mesh_group_add(geom_mesh *m, const geom_mesh_group *g, uint32_t *id);
/** Per-face group ids (n_faces entries), allocated on first call to the
 *  mutable accessor (initialised to GEOM_INVALID_INDEX); the const accessor
 *  returns NULL if there are none. NULL on out of memory. */
GEOM_API uint32_t *geom_mesh_face_groups(geom_mesh *m);
GEOM_API const uint32_t *geom_mesh_face_cgroups(const geom_mesh *m);
/** Material libraries (`mtllib` arguments), in file order. */
GEOM_API size_t geom_mesh_mtllib_count(const geom_mesh *m);
GEOM_API const char *geom_mesh_mtllib_get(const geom_mesh *m, size_t i);
GEOM_API geom_status geom_mesh_mtllib_add(geom_mesh *m, const char *name);

/** Polylines (OBJ `l`, feature edges): lists of vertex indices. */
GEOM_API size_t geom_mesh_polyline_count(const geom_mesh *m);
/** View of polyline i: *n vertices at *verts (valid until polylines change). */
GEOM_API geom_status geom_mesh_polyline_get(const geom_mesh *m, size_t i, size_t *n,
                                   const uint32_t **verts);
GEOM_API geom_status geom_mesh_polyline_add(geom_mesh *m, size_t n, const uint32_t *verts);

/* ---------------------------------------------------------------- queries */

/** Bounding box of live vertices (empty box for no vertices). */
GEOM_API geom_aabb geom_mesh_bbox(const geom_mesh *m);

/**
 * Boundary loops: *n_loops receives their number. If loop_of_halfedge is
 * non-NULL it receives, per halfedge, the loop id of a boundary halfedge and
 * GEOM_INVALID_INDEX otherwise (n_halfedges entries).
 */
GEOM_API geom_status geom_mesh_boundary_loops(const geom_mesh *m, size_t *n_loops,
                                     uint32_t *loop_of_halfedge);

/**
 * Connected components over live faces and edges (isolated vertices are
 * components of their own). *n receives the count; vertex_component
 * (n_vertices entries) and face_component (n_faces) may be NULL.
 */
GEOM_API geom_status geom_mesh_components(const geom_mesh *m, size_t *n, uint32_t *vertex_component,
                                 uint32_t *face_component);

/** Per-component topology, and the mesh's summary. */
typedef struct geom_mesh_topology {
    size_t vertices, edges, faces;   /**< live counts */
    size_t boundary_loops;
    size_t components;
    long euler;                      /**< V - E + F */
    long genus;                      /**< sum over components of (2 - chi_c - b_c) / 2 */
    bool manifold;                   /**< no defects found by geom_mesh_validate */
    bool closed;                     /**< no boundary halfedges */
    size_t degenerate_faces;         /**< see geom_mesh_face_is_degenerate */
    size_t isolated_vertices;
} geom_mesh_topology;

/** Fill *t. components/genus: isolated vertices count as components of
 *  genus 0. */
GEOM_API geom_status geom_mesh_topology_summary(const geom_mesh *m, geom_mesh_topology *t);

/**
 * A face is degenerate when its area (Newell normal length / 2) is at most
 * 1e-14 times the square of its longest edge, or it has two coincident
 * vertices.
 */
GEOM_API bool geom_mesh_face_is_degenerate(const geom_mesh *m, uint32_t f);

typedef enum geom_mesh_defect_kind {
    GEOM_MESH_DEFECT_BAD_INDEX = 1,          /**< a link points outside its array */
    GEOM_MESH_DEFECT_NEXT_PREV = 2,          /**< prev(next(h)) != h */
    GEOM_MESH_DEFECT_FACE_CYCLE = 3,         /**< a face's cycle does not return / has mixed faces */
    GEOM_MESH_DEFECT_VERTEX_HALFEDGE = 4,    /**< outgoing halfedge does not start at v */
    GEOM_MESH_DEFECT_BOUNDARY_NOT_FIRST = 5, /**< boundary vertex whose stored halfedge is interior */
    GEOM_MESH_DEFECT_NONMANIFOLD_VERTEX = 6, /**< more than one boundary gap at a vertex */
    GEOM_MESH_DEFECT_DELETED_REFERENCE = 7,  /**< a live element references a deleted one */
    GEOM_MESH_DEFECT_SMALL_FACE = 8,         /**< face with fewer than 3 edges */
    GEOM_MESH_DEFECT_CHANNEL = 9             /**< corner index outside its pool */
} geom_mesh_defect_kind;

typedef struct geom_mesh_defect {
    geom_mesh_defect_kind kind;
    uint32_t element; /**< the halfedge, vertex or face concerned */
} geom_mesh_defect;

/**
 * Check every invariant of the data structure without asserting. Writes up
 * to max_defects defects (defects may be NULL when max_defects is 0) and the
 * total found to *n_defects. GEOM_OK even when defects exist (the count
 * says); GEOM_ERR_INVALID_ARG for a NULL mesh.
 */
GEOM_API geom_status geom_mesh_validate(const geom_mesh *m, geom_mesh_defect *defects,
                               size_t max_defects, size_t *n_defects);

/* --------------------------------------------------------- triangulation */

/**
 * Triangulation of a simple polygon of n >= 3 points (3*n doubles) lying
 * (nearly) in a plane, convex or not: the polygon is projected onto the
 * coordinate plane most orthogonal to its Newell normal (the projected
 * coordinates are the input doubles themselves, so the exact orient2d
 * predicate decides every orientation); tris receives (n-2)*3 indices into
 * the polygon, every triangle with the polygon's own winding.
 *  - n <= 64: ear clipping (Meisters 1975), the best-shaped ear first; ties
 *    (collinear vertices) are resolved so no zero-area triangle is made when
 *    another choice exists. Triangles in clipping order.
 *  - n > 64: monotone decomposition (Lee & Preparata 1977; de Berg et al.,
 *    "Computational Geometry", 3rd ed., ch. 3) in O(n log n) time and about
 *    100 bytes of scratch per vertex: a top-to-bottom sweep with a balanced
 *    status tree adds the diagonals that cut the polygon into y-monotone
 *    pieces, each triangulated in linear time. Every triangle is strictly
 *    positive (exact orient2d) except where a repeated vertex or a zero-width
 *    spike forces a zero-area one (one per such vertex; those come first).
 *    Then the pieces' triangles, piece by piece, each piece's from its
 *    highest vertex down. No shape optimisation: triangles are long and thin
 *    where the polygon is (no Delaunay flips). About 0.05 s of CPU for
 *    100,000 vertices, 1.4 s for 1,000,000 (BENCHMARKS.md). Weakly simple
 *    polygons (holes joined by bridges walked both ways, as
 *    geom_mesh_clip_plane's caps) go through the sweep too.
 *  - Non-simple input (self-intersecting or overlapping sides: the sweep
 *    finds its order inconsistent and rejects it), or a monotone piece whose
 *    stack triangulation would make a non-positive triangle: the ear clipper
 *    (grid-bounded emptiness tests: about n^1.4 on random polygons, up to
 *    quadratic) does the whole polygon, or that piece. Its fallbacks (a
 *    collinear vertex, any convex vertex, any vertex) always give n-2
 *    triangles forming a combinatorial triangulation of the polygon (every
 *    side once, every diagonal twice), which may overlap for such input.
 * Allocates O(n) scratch (GEOM_ERR_NOMEM). GEOM_ERR_DEGENERATE for a
 * zero-area polygon (a fan is still written), GEOM_ERR_INVALID_ARG for n < 3,
 * NULL pointers or a non-finite coordinate (a fan is written in that last
 * case too).
 */
GEOM_API geom_status geom_polygon_triangulate(size_t n, const double *pts, uint32_t *tris);

/** Triangulate every face with more than three vertices in place (as
 *  geom_polygon_triangulate; O(n log n) in the face size), keeping corner-channel indices, face channels (copied
 *  to the new faces) and face groups. *n_new_faces (may be NULL) receives the
 *  number of faces added. GEOM_ERR_INVALID_ARG (mesh unchanged) if such a
 *  face has a non-finite vertex position; GEOM_ERR_NOMEM. */
GEOM_API geom_status geom_mesh_triangulate(geom_mesh *m, size_t *n_new_faces);

/* --------------------------------------------------------------- normals */

/** Face normal by Newell's method (exact for planar polygons, a robust
 *  average for non-planar ones), normalised; out is 3 doubles. A degenerate
 *  face gives (0,0,0) and GEOM_ERR_DEGENERATE. */
GEOM_API geom_status geom_mesh_face_normal(const geom_mesh *m, uint32_t f, double out[3]);

typedef enum geom_normal_weight {
    GEOM_NORMAL_WEIGHT_ANGLE = 0,   /**< incident angle (Thuermer & Wuethrich 1998); default */
    GEOM_NORMAL_WEIGHT_UNIFORM = 1, /**< each incident face counts once (Gouraud) */
    GEOM_NORMAL_WEIGHT_AREA = 2,    /**< face area (unnormalised Newell normals) */
    GEOM_NORMAL_WEIGHT_MAX = 3      /**< Max 1999: sin(angle) / (|e1| |e2|) per corner */
} geom_normal_weight;

/**
 * Vertex normals with the given weighting into `normals` (3*n_vertices
 * doubles), normalised. Degenerate faces contribute nothing; a vertex
 * without a usable face (isolated, or only degenerate faces) gets (0,0,0)
 * and is counted in *n_zero (may be NULL; live vertices only, deleted ones
 * get a zero normal uncounted). Never produces NaN. Max weights are negative
 * at reflex corners of non-convex polygons, as sin(angle) implies.
 * Accuracy: each normal within ~1e-15 (a few ulp) of the exactly weighted
 * sum, normalised.
 */
GEOM_API geom_status geom_mesh_vertex_normals(const geom_mesh *m, geom_normal_weight weight,
                                     double *normals, size_t *n_zero);

typedef struct geom_corner_normal_options {
    geom_normal_weight weight;
    /** Edges whose dihedral angle exceeds this (degrees) are hard; 0 means
     *  the default 180 (no crease splitting). */
    double crease_degrees;
    /** Nonzero: also split at seams of this CORNER channel (e.g. the "uv"
     *  channel's id + 1; 0 = none). */
    uint32_t split_at_channel_plus_one;
} geom_corner_normal_options;

/**
 * Corner normals: stores (adding or replacing) the CORNER channel "normal":
 * around each vertex, corners are grouped into fans bounded by hard edges
 * (dihedral angle above the crease angle, boundary edges, and optionally
 * seams of another corner channel); each fan gets the weighted average of
 * its faces' normals, so hard edges stay hard. *id receives the channel id.
 */
GEOM_API geom_status geom_mesh_corner_normals(geom_mesh *m, const geom_corner_normal_options *opt,
                                     uint32_t *id);

/* --------------------------------------------------- tangents and UV data */

/**
 * Per-corner tangent frames from the CORNER channels "uv" (2) and "normal"
 * (3; computed with default options if missing), compatible with
 * MikkTSpace (the convention Blender and glTF viewers use): per-face
 * tangents from UV derivatives, accumulated per (vertex, normal, uv) corner
 * group with angle weights, orthogonalised against the normal
 * (Gram-Schmidt); w = +1 or -1 is the bitangent sign so that
 * bitangent = w * cross(normal, tangent). Stores the CORNER channel
 * "tangent" (4 comps). Faces with degenerate UVs get a tangent built from
 * the normal alone. Polygons with more than four sides are fan-triangulated
 * for the per-face tangents. Corners are grouped by (vertex, normal value,
 * uv value): unlike MikkTSpace, two distinct vertices at the same position
 * are not merged. GEOM_ERR_INVALID_ARG if there is no "uv" channel.
 */
GEOM_API geom_status geom_mesh_tangents(geom_mesh *m, uint32_t *id);

typedef struct geom_uv_report {
    size_t charts;            /**< connected components of faces across non-seam edges */
    size_t seam_edges;        /**< edges whose two sides have different uv indices */
    size_t flipped_faces;     /**< faces whose uv-space signed area is negative */
    size_t degenerate_uv_faces; /**< zero uv-space area, or a missing uv index (such
                                     faces belong to no chart) */
    double uv_area;           /**< total |uv-space area| */
    double uv_min[2], uv_max[2];
} geom_uv_report;

/**
 * UV data for renderers from the CORNER channel `uv_channel` (2 comps):
 * the report, and optionally per-chart bounds (chart_bounds: 4 doubles per
 * chart, umin vmin umax vmax; query the chart count first with NULL),
 * per-face chart ids (n_faces entries) and per-edge seam flags (n_edges
 * bytes, 1 on seams). Any of the output arrays may be NULL.
 */
GEOM_API geom_status geom_mesh_uv_data(const geom_mesh *m, uint32_t uv_channel, geom_uv_report *report,
                              double *chart_bounds, uint32_t *face_chart, uint8_t *seam_edge);

/* ---------------------------------------------------------- feature edges */

typedef enum geom_feature_kind {
    GEOM_FEATURE_BOUNDARY = 1,
    GEOM_FEATURE_CREASE = 2,
    GEOM_FEATURE_SILHOUETTE = 4
} geom_feature_kind;

typedef struct geom_feature_options {
    unsigned kinds;        /**< OR of geom_feature_kind; 0 = boundary | crease */
    double crease_degrees; /**< dihedral threshold; 0 = 30 degrees */
    double eye[3];         /**< eye point for silhouettes */
} geom_feature_options;

/**
 * Feature edges, joined into polylines and appended to m's polylines
 * (chained through vertices where exactly two feature edges meet; closed
 * loops repeat their first vertex at the end). edge_kind (n_edges bytes,
 * may be NULL) receives the kinds per edge. A silhouette edge is an interior
 * edge whose faces n0, n1 satisfy (e.n0)(e.n1) <= 0 with e the vector from
 * the eye to the edge's midpoint. *n_polylines (may be NULL) receives the
 * number added.
 */
GEOM_API geom_status geom_mesh_features(geom_mesh *m, const geom_feature_options *opt, uint8_t *edge_kind,
                               size_t *n_polylines);

/* ------------------------------------------------------------- clipping */

typedef struct geom_clip_options {
    /** Nonzero: close the cut of a closed mesh with cap faces (triangulated
     *  by geom_polygon_triangulate, then Lawson flips), which get interpolated-free attributes: "normal"
     *  (CORNER or FACE, 3 comps) = the cap's outward normal, i.e. minus the
     *  unit plane normal -(a,b,c)/|(a,b,c)|, other CORNER and FACE channels
     *  zero (VERTEX channels are those of the shared cut vertices). */
    int cap;
} geom_clip_options;

/**
 * Keep the part of m where a*x + b*y + c*z + d >= 0 (plane = 4 doubles),
 * writing a new mesh to *out: faces cut by the plane are split (polygons stay
 * polygons), vertex and corner channels are interpolated linearly along cut
 * edges, face channels copied. Vertices within 1e-12 (relative to the bbox)
 * of the plane are snapped onto it so no sliver faces are made.
 * When nothing is cut the result is a clone; otherwise tags and polylines
 * are dropped, and a face lying in the plane is kept only if it faces away
 * from the kept side. GEOM_ERR_DEGENERATE for a zero plane normal.
 */
GEOM_API geom_status geom_mesh_clip_plane(const geom_mesh *m, const double plane[4],
                                 const geom_clip_options *opt, geom_mesh **out);

/**
 * Clip against the six planes of a view frustum given by a view-projection
 * matrix (OpenGL clip convention, Gribb-Hartmann plane extraction).
 */
GEOM_API geom_status geom_mesh_clip_frustum(const geom_mesh *m, geom_mat4 view_proj,
                                   const geom_clip_options *opt, geom_mesh **out);

/* ------------------------------------------------------------ as arrays */

/**
 * The half-edge connectivity as arrays of n_halfedges uint32 each (any may
 * be NULL): next, prev, vertex (the vertex h points to) and face
 * (GEOM_INVALID_INDEX on a boundary); opposite is h ^ 1, edge h >> 1.
 * Deleted elements keep whatever the mesh holds for them.
 * GEOM_OK; GEOM_ERR_INVALID_ARG for a NULL mesh.
 */
GEOM_API geom_status geom_mesh_halfedge_arrays(const geom_mesh *m, uint32_t *next, uint32_t *prev,
                                               uint32_t *vertex, uint32_t *face);

/**
 * Every vertex's ring as one compressed array: the elements a vertex
 * circulator of `kind` (GEOM_MESH_CIRC_VERTEX_OUTGOING, _FACES or
 * _VERTICES) visits, in its order, for vertex v at items[offsets[v] ..
 * offsets[v+1]). offsets: n_vertices + 1 values; items: `capacity` values
 * (NULL allowed with capacity 0). *count receives the total (at most
 * n_halfedges); deleted vertices get an empty ring.
 * GEOM_OK; GEOM_ERR_LIMIT when capacity < *count (offsets and *count are
 * still complete: call again with room for *count); GEOM_ERR_INVALID_ARG
 * for NULL m/offsets/count or another kind.
 */
GEOM_API geom_status geom_mesh_vertex_rings(const geom_mesh *m, geom_mesh_circ_kind kind,
                                            size_t *offsets, uint32_t *items, size_t capacity,
                                            size_t *count);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_MESH_H */
