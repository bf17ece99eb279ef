/*
 * libgeom iso: isosurfaces of scalar fields on regular grids by a
 * topologically correct marching cubes.
 *
 *  - Fields: the implicit module's one field type (geom_implicit_field:
 *    value, optional gradient, optional batches and bounds, user pointer,
 *    exact/sampled flag; geom_iso_field is a deprecated alias), a helper
 *    over a dense sampled grid of floats or doubles (geom_implicit_grid,
 *    alias geom_iso_grid: trilinear value, central-difference gradient),
 *    and adapters from the `implicit` module's
 *    compiled expressions and sampled volumes (geom_iso_field_from_expr,
 *    geom_iso_field_from_volume, geom_iso_grid_from_volume); any other
 *    function plugs in through the callbacks.
 *  - Extraction: each grid cell reproduces the topology of the trilinear
 *    interpolant of its eight corner values, tunnels and interior
 *    ambiguities included (the guarantee of Chernyaev's Marching Cubes 33
 *    with a correct interior test, Custodio et al. 2013, and of Grosso's
 *    TMC, 2016): face ambiguities are resolved by the asymptotic decider
 *    (Nielson and Hamann 1991), interior ones by an analysis of the
 *    interpolant's sign regions inside the cell (see geom_iso_extract). The
 *    output is an indexed triangle mesh whose vertices are shared by edge
 *    id, manifold, and closed wherever the surface stays inside the box;
 *    optional caps close it against the box faces.
 *  - Large grids are processed in slabs of cell layers with bounded memory
 *    (the field is evaluated two node layers at a time), in parallel across
 *    slabs with OpenMP when the library was built with it; slabs are merged
 *    in order, so the output is identical whatever the number of threads.
 *
 * Sign convention: by default a point is inside when f <= iso and outside
 * when f > iso (geom_iso_options::inside selects f >= iso instead): the
 * library's one inside convention, the same as marching squares'
 * (geom_implicit_contour), samples exactly equal to iso included, so a
 * plane z = const of the grid gives the same crossing edges in 2D and 3D.
 * Triangles are counter-clockwise seen from outside: their normals point
 * away from the inside (toward increasing f by default).
 *
 * Nothing here keeps global state or prints. The field's callbacks must be
 * safe to call concurrently when more than one thread is used.
 */
#ifndef GEOM_ISO_H
#define GEOM_ISO_H

#include "geom/core.h"
#include "geom/implicit.h"
#include "geom/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif


/* ------------------------------------------------------------------ fields */

/*
 * The field and the grid are the implicit module's (geom/implicit.h): one
 * field type for marching squares and marching cubes, one grid
 * description for volumes and sampled grids. The names below are
 * deprecated aliases kept so that earlier code compiles unchanged (member
 * names and meanings are the same). The one change for earlier iso code:
 * a gradient callback now returns the field's value at p (double) instead
 * of void (geom_implicit_grad_fn).
 */

/** Deprecated alias of geom_implicit_value_fn. */
typedef geom_implicit_value_fn geom_iso_value_fn;
/** Deprecated alias of geom_implicit_grad_fn (returns the value, fills g). */
typedef geom_implicit_grad_fn geom_iso_gradient_fn;
/** Deprecated alias of geom_implicit_values_fn. */
typedef geom_implicit_values_fn geom_iso_values_fn;
/** Deprecated alias of geom_implicit_gradients_fn. */
typedef geom_implicit_gradients_fn geom_iso_gradients_fn;
/** Deprecated alias of geom_implicit_bounds_fn. */
typedef geom_implicit_bounds_fn geom_iso_bounds_fn;

/** Deprecated alias of geom_implicit_field (the same struct). */
typedef struct geom_implicit_field geom_iso_field;

/* ------------------------------------------------------------ sampled grid */

/** Deprecated alias of geom_implicit_scalar (the same enum and values). */
typedef enum geom_implicit_scalar geom_iso_scalar;
#define GEOM_ISO_SCALAR_F32 GEOM_IMPLICIT_SCALAR_F32 /**< deprecated alias */
#define GEOM_ISO_SCALAR_F64 GEOM_IMPLICIT_SCALAR_F64 /**< deprecated alias */

/** Deprecated alias of geom_implicit_grid (the same struct: dims, type,
 *  data, spacing, origin; big_endian is ignored here). The samples are
 *  borrowed (not copied). */
typedef struct geom_implicit_grid geom_iso_grid;

/**
 * Check a grid description: GEOM_OK, or GEOM_ERR_INVALID_ARG (NULL grid or
 * data, a zero dimension, a bad type, a negative or non-finite spacing, a
 * non-finite origin), GEOM_ERR_LIMIT (sample count overflows size_t).
 */
GEOM_API geom_status geom_iso_grid_check(const geom_implicit_grid *g);

/**
 * Trilinear interpolation of the samples at p (3 doubles), by
 * geom_implicit_samples_value (the library's one interpolator: a volume
 * and a grid of the same samples agree bit for bit). Points outside
 * the sample box are clamped onto it. Exact (the stored sample, converted
 * to double) at sample positions whose offset from the origin divided by
 * the spacing is computed exactly (e.g. power-of-two spacings). NaN
 * coordinates give NaN. g must have passed geom_iso_grid_check.
 */
GEOM_API double geom_iso_grid_value(const geom_implicit_grid *g, const double p[3]);

/**
 * Gradient at p (3 doubles) into grad (3 doubles): the trilinear
 * interpolation of the per-sample central differences
 * (s[i+1] - s[i-1]) / (2 spacing), one-sided differences on the border and
 * 0 along an axis with one sample. Second-order accurate at samples for
 * smooth data. Outside the box, the gradient at the clamped point.
 */
GEOM_API void geom_iso_grid_gradient(const geom_implicit_grid *g, const double p[3], double grad[3]);

/** Callbacks over a grid (user = the const geom_implicit_grid *): value, and
 *  gradient into grad returning the value (geom_implicit_grad_fn). */
GEOM_API double geom_iso_grid_value_cb(void *user, const double p[3]);
GEOM_API double geom_iso_grid_gradient_cb(void *user, const double p[3], double grad[3]);

/**
 * Fill *out with g's callbacks (value, gradient, no batch, exact = 0).
 * g must outlive the field. GEOM_ERR_INVALID_ARG as geom_iso_grid_check.
 */
GEOM_API geom_status geom_iso_field_from_grid(const geom_implicit_grid *g, geom_implicit_field *out);

/* -------------------------------------------------------------- extraction */

/** geom_iso_options::error choices. */
enum {
    GEOM_ISO_ERROR_AUTO = 0,   /**< measure when the field is exact */
    GEOM_ISO_ERROR_ALWAYS = 1, /**< measure against whatever the field is */
    GEOM_ISO_ERROR_NEVER = 2
};

/** Options of the extraction; zero-initialised (or NULL) = defaults. */
typedef struct geom_iso_options {
    double iso;          /**< the isovalue (default 0), finite */
    /** geom_implicit_refine, as geom_implicit_contour_options::refine:
     *  refine each vertex on its edge by the library's root finder
     *  (geom_implicit_bracket_root: Illinois regula falsi with bisection,
     *  until the bracket ends are adjacent doubles) when the field is exact
     *  (GEOM_IMPLICIT_REFINE_AUTO, 0, the default), always (_ALWAYS: also
     *  an interpolant of samples given as a field), or never (_NEVER: linear
     *  interpolation of the node values). geom_iso_extract_grid never
     *  refines (its field is linear along the grid's edges). Before this
     *  version, 0 meant never and any nonzero value "when exact": pass
     *  GEOM_IMPLICIT_REFINE_NEVER for the old default. Other values
     *  refine nothing (as in geom_implicit_contour). */
    int refine;
    int max_iterations;  /**< root finding iterations per edge; 0 = 64 */
    /** Nonzero: compute unit vertex normals, from field->gradient when
     *  given, else by central differences of value() with a step of 1e-3
     *  of the cell size (for geom_iso_extract_grid: the grid's gradient). */
    int normals;
    /** Nonzero: close the surface against the box faces where it leaves
     *  the box (caps), so the result bounds the inside part of the box. */
    int caps;
    int error;           /**< GEOM_ISO_ERROR_* (default AUTO) */
    /** Threads: 0 = automatic (up to the OpenMP default, fewer for small
     *  grids), 1 = serial, n = at most n (one per slab at most). The output
     *  does not depend on it. Without OpenMP, always serial. */
    int threads;
    /** Cell layers (along z) per slab; 0 = automatic (a function of the
     *  grid size only, never of the thread count). */
    size_t slab_layers;
    /** For the result and temporaries; NULL = libc. Called from every
     *  extraction thread when more than one is used: it must then be
     *  thread-safe. */
    const geom_allocator *alloc;
    /** Which side of the isovalue is inside: GEOM_ISO_INSIDE_BELOW (0, the
     *  default: f <= iso, the surface at iso + epsilon) or
     *  GEOM_ISO_INSIDE_ABOVE (f >= iso, the surface at iso - epsilon: a CT
     *  volume, dense inside). Triangles are counter-clockwise and normals
     *  point away from the inside either way, and caps close the inside
     *  part. Above is the extraction of -f at -iso (negation is exact, so
     *  the vertices are the same; for a grid, a negated copy of the
     *  samples is made). Any other value: GEOM_ERR_INVALID_ARG. */
    int inside;
    /** Progress (NULL: none): called with the fraction (0..1] of the grid's
     *  slabs extracted, on the calling thread only (never concurrently,
     *  also when other threads extract). */
    void (*progress)(void *user, double fraction);
    void *progress_user; /**< passed to progress */
    /** Nonzero: sample every node of the grid (the dense path). Default:
     *  when the field has `bounds` (geom_iso_extract) or always
     *  (geom_iso_extract_grid), the grid is cut into blocks of
     *  block_size^3 cells, classified by recursive subdivision (an octree
     *  over the blocks: a box whose bounds lie strictly on one side of iso
     *  is classified whole, others are split down to single blocks; for a
     *  sampled grid, the min and max of each block's samples), and only
     *  the blocks the surface may cross are sampled. The output (vertices,
     *  triangles, their order, normals, caps, every report count except
     *  evaluations and cells_evaluated) is identical to the dense path's:
     *  a skipped block's nodes all lie strictly on one side of iso, so
     *  every cell in it is uniform and makes no surface. */
    int dense;
    /** Cells per block edge of the sparse path; 0 = 8. */
    size_t block_size;
    /** Largest number of points (vertices plus triangle samples) the
     *  error report measures (at least 5); 0 = 65536, SIZE_MAX = all. When there are
     *  more, every s-th vertex and every s-th surface triangle (by index,
     *  the first one included) is measured, s the smallest power of two
     *  that keeps the count within the budget (a power of two, so that
     *  geom_iso_extract_stream can sample as it goes): vertices are numbered in
     *  scan order, so the subset is spread evenly over the surface. The
     *  stride is in geom_iso_report::error_stride. */
    size_t error_samples;
} geom_iso_options;

/** geom_iso_options::inside values. */
enum {
    GEOM_ISO_INSIDE_BELOW = 0, /**< f <= iso is inside (default; the convention
                                    of geom_implicit_contour too) */
    GEOM_ISO_INSIDE_ABOVE = 1  /**< f >= iso is inside */
};

/** What an extraction did and achieved. */
typedef struct geom_iso_report {
    /** Over the vertices: max and mean of |f(v) - iso| / |grad f(v)| (a
     *  first-order estimate of the distance to the true isosurface; method
     *  GEOM_ERROR_SAMPLED), the gradient from field->gradient, else central
     *  differences. method GEOM_ERROR_NONE when not measured. evaluations:
     *  field evaluations made by the whole call (values, gradients count 1
     *  each; central differences count 6). */
    geom_error_report vertex_error;
    /** The same measure at triangle samples: each surface triangle's
     *  centroid and the midpoints of its edges (caps are not sampled). */
    geom_error_report sample_error;
    size_t unmeasured;       /**< samples left out: zero or non-finite gradient or value */
    double seconds;          /**< wall-clock time of the whole call */
    double error_seconds;    /**< part of it spent measuring the error */
    size_t cells;            /**< cells of the grid */
    size_t active_cells;     /**< cells the surface crosses */
    size_t ambiguous_faces;  /**< faces decided by the asymptotic decider */
    size_t tunnels;          /**< cells where two contours are joined by a tube */
    size_t iso_nodes;        /**< grid nodes with f == iso exactly */
    size_t nan_nodes;        /**< grid nodes with a NaN value (treated as +inf) */
    size_t refined;          /**< vertices refined by root finding */
    size_t slabs;            /**< slabs processed */
    int threads;             /**< threads used */
    /** Signed volume enclosed by all the triangles, caps included
     *  (divergence theorem): positive when they face away from the inside
     *  as they should; the inside part's volume when the surface is closed
     *  (e.g. with caps). */
    double signed_volume;
    /** The report every approximating operation gives (geom/core.h): max
     *  of vertex_error and sample_error, mean over the triangle samples,
     *  pieces = vertices and samples measured, seconds = the whole call,
     *  tolerance 0 (a fixed grid). */
    geom_error_report error;
    /** Cells whose corner values were computed (all cells on the dense
     *  path; those of the sampled blocks on the sparse path). */
    size_t cells_evaluated;
    /** Blocks of the sparse path: all, and those skipped because the
     *  surface provably does not cross them (0 and 0 on the dense path). */
    size_t blocks, blocks_skipped;
    /** Stride of the error sampling (1: every vertex and triangle sample
     *  measured; 0: not measured); see geom_iso_options::error_samples. */
    size_t error_stride;
    /** When nan_nodes > 0: the first grid node with a NaN value in scan
     *  order (layers of increasing z, rows of increasing y, then x), its
     *  node index (i, j, k) and its point; zeros otherwise. */
    size_t nan_first[3];
    double nan_point[3];
} geom_iso_report;

/** An extracted surface: an indexed triangle mesh. */
typedef struct geom_iso_surface {
    size_t n_vertices;
    double *xyz;          /**< 3 * n_vertices */
    double *normals;      /**< 3 * n_vertices unit normals, or NULL */
    size_t n_triangles;   /**< all triangles, caps included */
    uint32_t *tris;       /**< 3 * n_triangles vertex indices, counter-clockwise from outside */
    /** The first n_triangles - n_cap_triangles triangles are the
     *  isosurface; the last n_cap_triangles lie on the box faces. */
    size_t n_cap_triangles;
    geom_iso_report report;
    geom_allocator alloc; /**< the allocator used (internal) */
} geom_iso_surface;

/**
 * Marching cubes of `field` over the box bounds = {x0, y0, z0, x1, y1, z1}
 * (x0 < x1, ...) divided into res[0] x res[1] x res[2] cells: the field is
 * sampled at the nodes x_i = (x0 (n - i) + x1 i) / n (likewise y, z),
 * through field->values one row at a time when given.
 *
 * Classification: a node is inside when f <= iso, outside when f > iso;
 * NaN counts as +inf (outside), so the surface closes around undefined
 * regions. Equivalently, the surface extracted is the level set at
 * iso + epsilon for an infinitesimal epsilon > 0 (a symbolic perturbation):
 * every decision below is taken for that generic level, so grid values
 * exactly equal to iso cause no holes and no non-manifold or duplicate
 * faces. A vertex whose position would fall on a grid node (its edge
 * parameter 0 or 1, as for nodes with f == iso) is moved along its edge to
 * parameter tau or 1 - tau, with tau = 2^-20 or larger when the
 * coordinates need it to stay distinct in double precision: vertices never
 * coincide and no triangle has zero area.
 *
 * Topology: each cell reproduces the topology of the trilinear interpolant
 * of its corner values at iso + epsilon. On each face, a saddle (corners
 * alternating in sign) is resolved by the asymptotic decider (Nielson and
 * Hamann 1991): the inside corners are joined when the bilinear
 * interpolant's value at its saddle point is inside, the sign coming from
 * the 2x2 determinant ad - bc of the shifted corner values, computed with
 * an exact sign (ties resolved for iso + epsilon) and the same in both
 * cells sharing the face. The contours on the six faces are joined into
 * closed polygons. Which polygons bound one piece of surface (a tunnel
 * joins two) follows from the connectivity of the interpolant's sign
 * regions inside the cell: a sweep through the planes z = t, where the
 * slice topology changes only at the roots of the vertical edges and of a
 * quadratic in t (the slice's saddle crossing the isovalue); the level set
 * inside a cell has no closed piece (the trilinear interpolant has no
 * interior extremum), so its pieces are the classes of polygons separating
 * the same two regions.
 *
 * Triangulation: a polygon bounding a disk gets no new vertex when possible:
 * a quadrilateral is split along its shorter diagonal, larger polygons by
 * the triangulation minimising the sum of squared triangle areas; chords
 * between two vertices of one cell face are avoided (they would lie in the
 * face, on the neighbour's side too), and when every triangulation needs
 * one, the polygon becomes a fan around an inner vertex placed on the
 * interpolant's level set. Two polygons joined by a tunnel are connected by
 * a tube through a ring of inner vertices, placed where rays from a point of
 * the tunnel's core, in a plane across it, reach the interpolant's level
 * set; the cell's triangles are then checked for crossings (exact
 * orientation tests) and other planes, ring sizes and finally a zipper
 * through moved midpoints are tried until none cross. Inner vertices lie
 * strictly inside their cell. Topology is guaranteed; geometry is
 * self-intersection free for smooth fields (checked by CGAL on the test
 * suite) and, on random noise, for all but about one tunnel cell in a few
 * hundred, where no candidate tube avoids touching the cell's other
 * triangles.
 *
 * Geometry: vertices by linear interpolation of the node values along their
 * edge, then optionally (opt->refine, exact fields) by root finding on the
 * field restricted to the edge to full double precision. Each vertex is
 * shared by every triangle of its edge (vertices are numbered slab by slab,
 * in scan order, so the numbering is deterministic).
 *
 * Accuracy: the error report (see geom_iso_report) is filled when the
 * field is exact (or opt->error says so). With linear interpolation the
 * vertex error is O(h^2) for smooth f; with refinement, vertices are roots
 * of f to rounding, and the triangle samples show the O(h^2) chordal error.
 *
 * Memory: the field values of two node layers per slab in flight plus the
 * output; a 1024^3 grid of a procedural field takes well under 2 GiB.
 *
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL field, value, bounds, res
 * or out; non-finite or empty bounds; a zero resolution; cells so small
 * that two node coordinates round to the same double; non-finite iso);
 * GEOM_ERR_LIMIT (more than 2^32 - 2 vertices in all or 2^31 - 3 in one
 * slab, a resolution of 2^30 cells or more along an axis, or a grid too
 * large for size_t); GEOM_ERR_NOMEM. On error *out is zeroed (nothing to
 * free).
 */
GEOM_API geom_status geom_iso_extract(const geom_implicit_field *field, const double bounds[6],
                             const size_t res[3], const geom_iso_options *opt,
                             geom_iso_surface *out, geom_diag *diag);

/**
 * Marching cubes of a sampled grid over its own nodes (the samples; no
 * resampling): the cells are the (dims - 1) boxes between samples, the
 * values are the samples themselves. Everything else as geom_iso_extract;
 * the error is measured only when opt->error is GEOM_ISO_ERROR_ALWAYS
 * (against the trilinear interpolant, geom_iso_grid_value). Normals from
 * geom_iso_grid_gradient. A grid with fewer than 2 samples along an axis
 * gives an empty surface.
 * Statuses: as geom_iso_extract, GEOM_ERR_INVALID_ARG as geom_iso_grid_check.
 */
GEOM_API geom_status geom_iso_extract_grid(const geom_implicit_grid *grid, const geom_iso_options *opt,
                                  geom_iso_surface *out, geom_diag *diag);

/** One piece of a surface that geom_iso_extract_stream hands over, in
 *  order: the pieces together are geom_iso_extract's result. */
typedef struct geom_iso_chunk {
    size_t first_vertex;   /**< number of xyz[0] in the whole surface (0-based) */
    size_t n_vertices;     /**< new vertices in this chunk */
    const double *xyz;     /**< 3 * n_vertices doubles */
    /** 3 * n_vertices doubles; NULL exactly when there are no normals
     *  (no opt->normals), also in a chunk without vertices */
    const double *normals;
    size_t n_triangles;
    /** 3 * n_triangles vertex numbers of the whole surface, each below
     *  first_vertex + n_vertices (a triangle may use earlier chunks'
     *  vertices) */
    const uint32_t *tris;
    int caps; /**< nonzero: the cap triangles (the last chunk, no vertices) */
} geom_iso_chunk;

/** Receives each chunk (valid during the call only); a status other than
 *  GEOM_OK stops the extraction, which returns it. */
typedef geom_status (*geom_iso_chunk_fn)(void *user, const geom_iso_chunk *chunk);

/**
 * geom_iso_extract, handing the surface to fn chunk by chunk (one per slab
 * of cell layers, then one of cap triangles with opt->caps) instead of
 * building its arrays: the vertices, triangles and normals, their order
 * and the report are those of geom_iso_extract (the chunks' vertices
 * concatenated are its xyz, their triangles its tris; the report's mean
 * errors may differ in the last bits, summed in another order), without
 * the arrays of the whole surface (for writing a large isosurface, e.g.
 * with geom_meshio_write_soup_part). Memory: each slab is renumbered,
 * handed over and its arrays reused by a later slab as soon as it and
 * every slab before it are done, while the other threads go on with later
 * slabs, at most as many slabs ahead of the hand-over as there are threads
 * (a thread that would go further waits, without using the CPU), so the
 * peak is a few slabs' arrays (about 38 MiB for geom-iso at 512^3 on two
 * tori with 2 threads, 104 MiB when every slab was computed first). fn is
 * called on the calling thread only, in order (empty chunks are skipped),
 * possibly while other threads compute later slabs. out receives the counts (n_vertices,
 * n_triangles, n_cap_triangles) and the report; its arrays stay NULL.
 * Statuses: as geom_iso_extract, GEOM_ERR_INVALID_ARG for a NULL fn, and
 * fn's own status when it fails (on any error, the chunks given so far stay
 * given).
 */
GEOM_API geom_status geom_iso_extract_stream(const geom_implicit_field *field,
                                             const double bounds[6], const size_t res[3],
                                             const geom_iso_options *opt, geom_iso_chunk_fn fn,
                                             void *user, geom_iso_surface *out, geom_diag *diag);

/** Free what an extraction allocated and zero *s. NULL or a zeroed struct
 *  is a no-op. */
GEOM_API void geom_iso_surface_free(geom_iso_surface *s);

/**
 * Replace m's contents with the surface (geom_mesh_build of the triangle
 * soup; vertex i of the mesh is vertex i of the surface, face i triangle i),
 * adding the VERTEX channel "normal" when the surface has normals.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL); GEOM_ERR_NOMEM;
 * GEOM_ERR_LIMIT; GEOM_ERR_NONMANIFOLD if the mesh builder had to repair
 * anything (it never should: the mesh is then left as built).
 */
GEOM_API geom_status geom_iso_surface_to_mesh(const geom_iso_surface *s, geom_mesh *m, geom_diag *diag);

/**
 * Measure the error of any triangle mesh against a field: as
 * geom_iso_report::vertex_error and sample_error, for the n_vertices
 * vertices (3 doubles each) and the n_triangles triangles (3 indices each,
 * each < n_vertices). Any of the report pointers may be NULL.
 * *unmeasured (may be NULL) receives the samples left out.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL field/value, NULL arrays
 * with nonzero counts, an index out of range, non-finite iso).
 */
GEOM_API geom_status geom_iso_measure_error(const geom_implicit_field *field, double iso, size_t n_vertices,
                                   const double *xyz, size_t n_triangles, const uint32_t *tris,
                                   geom_error_report *vertex_error,
                                   geom_error_report *sample_error, size_t *unmeasured);

/* ------------------------------------------- fields from geom/implicit.h */

/**
 * Deprecated: geom_implicit_field_from_expr, which fills the same field
 * (value, exact gradient, values, gradients, bounds for the sparse path,
 * exact = 1), with a status. e must outlive the field.
 * GEOM_ERR_INVALID_ARG for NULL e or out (out zeroed when not NULL).
 */
GEOM_API geom_status geom_iso_field_from_expr(const geom_implicit_expr *e, geom_implicit_field *out);

/**
 * Deprecated: geom_implicit_field_from_volume, which fills the same field
 * (trilinear value, central-difference gradient, exact = 0), with a
 * status. v must outlive the field. GEOM_ERR_INVALID_ARG for NULL
 * arguments (out zeroed when not NULL).
 */
GEOM_API geom_status geom_iso_field_from_volume(const geom_implicit_volume *v, geom_implicit_field *out);

/**
 * Describe v's samples as a grid (borrowing the data: v must outlive the
 * grid), so that marching cubes reads them directly: the same as
 * geom_implicit_volume_get_desc. GEOM_ERR_INVALID_ARG for NULL arguments.
 */
GEOM_API geom_status geom_iso_grid_from_volume(const geom_implicit_volume *v, geom_implicit_grid *out);

/* ------------------------------------------------------------- estimates */

/**
 * The number of triangles geom_iso_extract(f, bounds, res, opt, ...) would
 * make, estimated before extracting. opt (NULL: defaults) gives the
 * isovalue, the inside side and whether caps are made (its other fields
 * are not used). The field is sampled on a grid of at most 40 cells per
 * axis over bounds (f->value at most 41^3 times, from the calling thread);
 * the cells with samples on both sides of iso are counted, scaled by (fine
 * cells per coarse cell)^(2/3) (the surface's area) and by 2 triangles per
 * crossed cell. With opt->caps, each coarse cell on a box face adds the cap
 * triangles the extraction makes there (its own rule, on the coarse
 * values), scaled to the fine cells it stands for: twice their number when
 * the face cell is inside, and for a cut one the inside fraction its
 * corners give plus about sqrt(fine cells) cut cells along the boundary;
 * exact when the resolution is at most 40 cells per axis (the coarse grid
 * is the grid). Accuracy: an estimate, not a bound. Exact scaling for
 * smooth surfaces larger than the coarse cells; features thinner than a
 * coarse cell are missed (an underestimate). Measured (test_iso_estimate)
 * against the extraction's count on spheres, a torus and a gyroid cut by
 * the box, caps on and off, both inside sides, 24, 60 and 120 cells per
 * axis: 0.96x to 1.00x of it (the test's bound is 0.9x to 1.1x).
 * GEOM_OK; GEOM_ERR_INVALID_ARG (NULL arguments, no value callback, a zero
 * res, an empty box, a non-finite opt->iso, an opt->inside other than
 * GEOM_ISO_INSIDE_BELOW / _ABOVE); GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_iso_estimate_triangles(const geom_implicit_field *f, const double bounds[6],
                                                 const size_t res[3], const geom_iso_options *opt,
                                                 double *triangles);

/**
 * As geom_iso_estimate_triangles for geom_iso_extract_grid(g, opt): every
 * cell of the grid is checked (one pass over the samples, no allocation),
 * so only the surface's triangles per crossed cell are estimated (2: 1.02x
 * to 1.04x of the count made on a sampled gyroid); with opt->caps the cap
 * triangles are counted exactly (the extraction's rule on every boundary
 * cell).
 * GEOM_OK; the statuses of geom_iso_grid_check; GEOM_ERR_INVALID_ARG for a
 * NULL triangles, a non-finite opt->iso or an invalid opt->inside.
 */
GEOM_API geom_status geom_iso_grid_estimate_triangles(const geom_implicit_grid *g,
                                                      const geom_iso_options *opt,
                                                      double *triangles);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_ISO_H */
