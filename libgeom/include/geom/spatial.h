/*
 * libgeom spatial: spatial indices (BVH, kd-tree, quadtree, octree) and the
 * queries a geometry user needs on them (nearest neighbours, radius, box,
 * frustum, ordered ray traversal, closest point and signed distance to a
 * triangle mesh).
 *
 * Contracts shared by every structure:
 *  - builds are deterministic: the same input gives the same tree, node for
 *    node, whatever the thread count (OpenMP is used where it pays; the
 *    `threads` option only changes the speed);
 *  - NaN/Inf coordinates are rejected with GEOM_ERR_INVALID_ARG and the index
 *    of the first bad element in the diag message; nothing is built;
 *  - nodes live in flat arrays (no per-node allocation); every structure has
 *    `_destroy` (NULL is a no-op) and reports its depth and bytes;
 *  - neighbour queries take the radius (not its square); a point at exactly
 *    the radius is inside. Results are sorted by distance, ties broken by the
 *    smaller index, so every answer is unique. Distances are computed as the
 *    correctly rounded-per-operation sum of squared coordinate differences,
 *    the same expression for every structure and for brute force, so results
 *    agree exactly with a brute-force scan;
 *  - boxes include their boundary.
 */
#ifndef GEOM_SPATIAL_H
#define GEOM_SPATIAL_H

#include "geom/core.h"
#include "geom/mesh.h" /* GEOM_INVALID_INDEX */

#ifdef __cplusplus
extern "C" {
#endif

/* ====================================================================== BVH */

/** Opaque bounding volume hierarchy. */
typedef struct geom_bvh geom_bvh;

/** Build algorithm of a BVH. */
typedef enum geom_bvh_method {
    GEOM_BVH_SAH = 0,  /**< binned surface area heuristic (Wald 2007) (default) */
    GEOM_BVH_LBVH = 1  /**< Morton-code linear BVH (Lauterbach et al. 2009): fast build */
} geom_bvh_method;

/** BVH build options; valid when zero-initialised. */
typedef struct geom_bvh_options {
    geom_bvh_method method;      /**< 0 = GEOM_BVH_SAH */
    uint32_t max_leaf_size;      /**< primitives per leaf at most; 0 = 4 */
    uint32_t bins;               /**< SAH bins per axis; 0 = 16 (at most 256) */
    int threads;                 /**< 0 = all available (OpenMP); the tree does not depend on it */
    const geom_allocator *alloc; /**< NULL = malloc; copied, need not outlive the call */
} geom_bvh_options;

/**
 * One node of the flat depth-first layout. Interior node i: count == 0, the
 * left child is node i + 1, the right child is node `index`, and `axis` is
 * the axis (0, 1, 2) the children were split along. Leaf: count >= 1 and its
 * primitives are prim_index[index .. index + count). Boxes are conservative:
 * they contain every primitive of the subtree exactly (computed in double
 * from the primitive bounds with min/max only, no rounding).
 */
typedef struct geom_bvh_node {
    geom_aabb box;
    uint32_t index;
    uint32_t count;
    uint32_t axis;
    uint32_t pad;
} geom_bvh_node;

/**
 * BVH over triangles. positions: 3*nv doubles; tris: 3*nt vertex indices.
 * Each triangle is bounded by the min/max of its three vertices.
 * Returns GEOM_OK; GEOM_ERR_INVALID_ARG for NULL pointers, a vertex index
 * >= nv, or a NaN/Inf coordinate (the diag names the first bad triangle and
 * its vertex); GEOM_ERR_NOMEM; GEOM_ERR_LIMIT if nt >= 2^31. nt == 0 gives a
 * valid BVH with zero nodes.
 */
GEOM_API geom_status geom_bvh_build_triangles(const double *positions, size_t nv,
                                              const uint32_t *tris, size_t nt,
                                              const geom_bvh_options *opt, geom_bvh **out,
                                              geom_diag *diag);

/**
 * BVH over n boxes (primitive i is boxes[i]). Same statuses as
 * geom_bvh_build_triangles; an empty box (min > max) or a NaN/Inf bound is
 * GEOM_ERR_INVALID_ARG naming the first bad box.
 */
GEOM_API geom_status geom_bvh_build_boxes(const geom_aabb *boxes, size_t n,
                                          const geom_bvh_options *opt, geom_bvh **out,
                                          geom_diag *diag);

/** Bounds callback: write the box of primitive i into *box. Called for each
 *  primitive once (LBVH) or three times (SAH: validation, the build's
 *  single-precision copy, the exact leaf boxes), possibly from several
 *  threads at once: it must give the same box each time. */
typedef void (*geom_bvh_bounds_fn)(void *user, size_t i, geom_aabb *box);

/** BVH over n primitives whose boxes come from fn (see geom_bvh_build_boxes). */
GEOM_API geom_status geom_bvh_build_callback(size_t n, geom_bvh_bounds_fn fn, void *user,
                                             const geom_bvh_options *opt, geom_bvh **out,
                                             geom_diag *diag);

/**
 * Refit after moving vertices: recompute every box bottom-up from the new
 * positions, keeping the topology. nt must equal the primitive count the BVH
 * was built with (and tris the same connectivity). Returns GEOM_OK,
 * GEOM_ERR_INVALID_ARG (NULL, nt mismatch, bad index, NaN/Inf; the BVH is
 * then left unchanged).
 */
GEOM_API geom_status geom_bvh_refit_triangles(geom_bvh *b, const double *positions, size_t nv,
                                              const uint32_t *tris, size_t nt);

/** Free a BVH. NULL is a no-op. */
GEOM_API void geom_bvh_destroy(geom_bvh *b);
/** The nodes (node 0 is the root); *count receives their number (may be NULL). */
GEOM_API const geom_bvh_node *geom_bvh_nodes(const geom_bvh *b, size_t *count);
/** Primitive indices referenced by the leaves; *count = primitive count. */
GEOM_API const uint32_t *geom_bvh_prim_indices(const geom_bvh *b, size_t *count);
/** Number of levels (0 for an empty BVH, 1 for a single leaf). */
GEOM_API size_t geom_bvh_depth(const geom_bvh *b);
/** Bytes held by the BVH (nodes, indices and the object itself). */
GEOM_API size_t geom_bvh_bytes(const geom_bvh *b);

/* ================================================================ neighbours */

/**
 * Variable-length answers of a batch of queries (radius and box queries), in
 * compressed rows: the answers of query q are index[offsets[q] ..
 * offsets[q+1]) with distance[...] alongside (NULL for box queries). Filled
 * by the query functions (which free what `out` held first, so one struct
 * can be reused); free with geom_neighbors_free. A zero-initialised struct
 * is empty.
 */
typedef struct geom_neighbors {
    size_t query_count;
    size_t *offsets;    /**< query_count + 1 entries */
    uint32_t *index;    /**< offsets[query_count] entries */
    double *distance;   /**< offsets[query_count] entries, or NULL */
    size_t capacity;    /**< allocated entries of index/distance (internal) */
    const geom_allocator *alloc; /**< allocator the arrays came from (internal) */
} geom_neighbors;

/** Free the arrays of `nb` and zero it. NULL is a no-op. */
GEOM_API void geom_neighbors_free(geom_neighbors *nb);

/**
 * Box queries over a BVH: for each of the m closed query boxes queries[q],
 * the primitives whose box meets it (boxes touching at a face, edge or
 * corner count), as row q of `out` in increasing primitive order (distance
 * NULL; CSR: out->offsets has m + 1 entries). prim_boxes holds the box of
 * every primitive (the BVH's primitive count of them, indexed by primitive
 * id): the boxes given to geom_bvh_build_boxes, or for a triangle BVH the
 * min/max of each triangle's vertices at the last build or refit. The node
 * boxes must contain them (as the builders make them); the answer is then
 * exactly the brute-force test of every primitive box, by comparisons only
 * (no rounding). A query with min > max on an axis is empty and meets
 * nothing; infinite bounds are allowed. Traversal: depth first from the
 * root, pruning nodes whose box misses the query; the queries run in
 * parallel chunks (`threads`, 0 = all available) and the output does not
 * depend on the thread count.
 * Returns GEOM_OK; GEOM_ERR_INVALID_ARG for NULL b/out, NULL queries with
 * m > 0, NULL prim_boxes with primitives, or a NaN bound (diag names the
 * query); GEOM_ERR_NOMEM (out is then empty); GEOM_ERR_LIMIT if the walk
 * outgrows the depth the BVH reports (not with the library's builders).
 */
GEOM_API geom_status geom_bvh_query_boxes(const geom_bvh *b, const geom_aabb *prim_boxes,
                                          const geom_aabb *queries, size_t m,
                                          geom_neighbors *out, int threads,
                                          geom_diag *diag);

/* ================================================================== kd-tree */

/** Opaque kd-tree over points in 2D or 3D. */
typedef struct geom_kdtree geom_kdtree;

/** kd-tree build options; valid when zero-initialised. */
typedef struct geom_kdtree_options {
    uint32_t leaf_size;          /**< points per leaf at most; 0 = 10 */
    int threads;                 /**< 0 = all available; the tree does not depend on it */
    const geom_allocator *alloc; /**< NULL = malloc (may be called from several threads) */
} geom_kdtree_options;

/**
 * kd-tree over n points of dimension dim (2 or 3): points is dim*n doubles
 * (copied). Each node splits at the median point along the widest axis of
 * its points (Friedman, Bentley and Finkel 1977); leaves hold at most
 * leaf_size points; duplicated points are fine (equal coordinates may sit on
 * both sides of a split). Returns GEOM_OK; GEOM_ERR_INVALID_ARG (NULL, dim
 * not 2 or 3, a NaN/Inf coordinate: the diag names the first bad point);
 * GEOM_ERR_LIMIT (n >= 2^32 - 1); GEOM_ERR_NOMEM. n == 0 is valid.
 */
GEOM_API geom_status geom_kdtree_build(const double *points, size_t n, int dim,
                                       const geom_kdtree_options *opt, geom_kdtree **out,
                                       geom_diag *diag);
/** Free a kd-tree. NULL is a no-op. */
GEOM_API void geom_kdtree_destroy(geom_kdtree *t);
/** Node count, depth (levels) and bytes held. */
GEOM_API size_t geom_kdtree_node_count(const geom_kdtree *t);
GEOM_API size_t geom_kdtree_depth(const geom_kdtree *t);
GEOM_API size_t geom_kdtree_bytes(const geom_kdtree *t);

/**
 * k nearest neighbours of nq query points (dim*nq doubles, the tree's dim),
 * in parallel over the queries. Query q's answers go to index[q*k ..
 * q*k+k) and distance[q*k ..] (either may be NULL), nearest first, ties by
 * the smaller index; when the tree has fewer than k points the rest is
 * GEOM_INVALID_INDEX and +Inf. Distances are Euclidean, computed as
 * sqrt(dx*dx + dy*dy + dz*dz) (the order of the squared sums decides).
 * Returns GEOM_OK or GEOM_ERR_INVALID_ARG (NULL tree or queries, or a
 * NaN/Inf query: the call is rejected before any work, the diag names the
 * first bad query).
 */
GEOM_API geom_status geom_kdtree_knn(const geom_kdtree *t, const double *queries, size_t nq,
                                     size_t k, uint32_t *index, double *distance,
                                     int threads, geom_diag *diag);

/**
 * All points within distance r (inclusive: sqrt(d2) <= r) of each of nq
 * queries, sorted by distance then index, into `out`. r must be >= 0 and
 * finite. Statuses as geom_kdtree_knn, plus GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_kdtree_radius(const geom_kdtree *t, const double *queries, size_t nq,
                                        double r, geom_neighbors *out, int threads,
                                        geom_diag *diag);

/**
 * Points inside the closed box [lo, hi] (dim doubles each), in increasing
 * index order, as one row of `out` (distance NULL). Returns GEOM_OK,
 * GEOM_ERR_INVALID_ARG (NaN bounds), GEOM_ERR_NOMEM. lo > hi on an axis
 * gives an empty answer.
 */
GEOM_API geom_status geom_kdtree_box(const geom_kdtree *t, const double *lo, const double *hi,
                                     geom_neighbors *out);

/* ========================================================= quadtree / octree */

/** Opaque quadtree (2D) or octree (3D) over points, segments or triangles. */
typedef struct geom_octree geom_octree;

/** Options; valid when zero-initialised. */
typedef struct geom_octree_options {
    uint32_t bucket_size;        /**< a node with more items splits; 0 = 16 */
    uint32_t max_depth;          /**< deepest level (root = 0); 0 = the finest the
                                      codes resolve: 19 (octree), 28 (quadtree) */
    int balance;                 /**< nonzero: 2:1 balance (neighbouring leaves,
                                      across faces, edges and corners, differ by at
                                      most one level; every node then has all
                                      2^dim children) */
    int threads;                 /**< 0 = all available; the tree does not depend on it */
    const geom_allocator *alloc; /**< NULL = malloc */
} geom_octree_options;

/**
 * One node. Children are contiguous: nodes[first_child ..] in increasing
 * octant order for the octants set in child_mask (octant bit 0 = +x half,
 * bit 1 = +y, bit 2 = +z). The items of the subtree are
 * items[item_start .. item_start + item_total); the first own_count of them
 * are stored at this node itself (every item of a leaf; for segments and
 * triangles also the elements that straddle the children's cells). `cell`
 * is the node's square/cube (z extent 0 in 2D); `bounds` is the tight box of
 * the subtree's items (empty when it has none): queries prune with it, so
 * they are exact whatever the rounding of the cells.
 */
typedef struct geom_octree_node {
    geom_aabb cell;
    geom_aabb bounds;
    uint32_t first_child; /**< GEOM_INVALID_INDEX for a leaf */
    uint32_t child_mask;
    uint32_t item_start;
    uint32_t item_total;
    uint32_t own_count;
    uint32_t level;
} geom_octree_node;

/**
 * Linear (Morton-ordered) build: items are sorted by the Morton code of
 * their cell (19 bits per axis in 3D, 28 in 2D) in O(n log n) (radix sort), then the
 * tree is cut top-down from the sorted codes; nodes and items are flat
 * arrays. An element sits at the deepest cell that contains its box (the
 * root if it spans the middle), a point at the deepest needed. A node with
 * at most bucket_size items, at max_depth, or whose items all share one
 * cell code (coincident points: a million copies of one point make one
 * leaf) is a leaf: it does not split further, so depth and memory stay
 * bounded (depth <= max_depth, nodes <= items * (max_depth + 1)).
 * Points: dim*n doubles, dim 2 (quadtree) or 3 (octree). Returns GEOM_OK;
 * GEOM_ERR_INVALID_ARG (NULL, bad dim, NaN/Inf: the diag names the first
 * bad point); GEOM_ERR_LIMIT (n >= 2^32 - 1); GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_octree_build_points(const double *points, size_t n, int dim,
                                              const geom_octree_options *opt, geom_octree **out,
                                              geom_diag *diag);
/** Quadtree over segments: positions 2*nv doubles, segs 2*ns indices. Same
 *  statuses (the diag names the first bad segment). */
GEOM_API geom_status geom_octree_build_segments(const double *positions, size_t nv,
                                                const uint32_t *segs, size_t ns,
                                                const geom_octree_options *opt, geom_octree **out,
                                                geom_diag *diag);
/** Octree over triangles: positions 3*nv doubles, tris 3*nt indices. */
GEOM_API geom_status geom_octree_build_triangles(const double *positions, size_t nv,
                                                 const uint32_t *tris, size_t nt,
                                                 const geom_octree_options *opt, geom_octree **out,
                                                 geom_diag *diag);
/** Free. NULL is a no-op. */
GEOM_API void geom_octree_destroy(geom_octree *t);
/** Nodes (node 0 is the root; none for an empty tree). */
GEOM_API const geom_octree_node *geom_octree_nodes(const geom_octree *t, size_t *count);
/** Item (point/element) indices in tree order; *count = number of items. */
GEOM_API const uint32_t *geom_octree_items(const geom_octree *t, size_t *count);
/** Dimension (2 or 3), levels (0 empty, 1 root only) and bytes held. */
GEOM_API int geom_octree_dim(const geom_octree *t);
GEOM_API size_t geom_octree_depth(const geom_octree *t);
GEOM_API size_t geom_octree_bytes(const geom_octree *t);

/** kNN as geom_kdtree_knn, on a point tree (GEOM_ERR_INVALID_ARG otherwise). */
GEOM_API geom_status geom_octree_knn(const geom_octree *t, const double *queries, size_t nq,
                                     size_t k, uint32_t *index, double *distance, int threads,
                                     geom_diag *diag);
/** Radius query as geom_kdtree_radius, on a point tree. */
GEOM_API geom_status geom_octree_radius(const geom_octree *t, const double *queries, size_t nq,
                                        double r, geom_neighbors *out, int threads,
                                        geom_diag *diag);
/** Items whose box meets the closed box [lo, hi] (dim doubles each), in
 *  increasing index order (one row, distance NULL). */
GEOM_API geom_status geom_octree_box(const geom_octree *t, const double *lo, const double *hi,
                                     geom_neighbors *out);
/**
 * Frustum query: items whose box is not entirely on the negative side of
 * any of the six planes (planes: 24 doubles, plane i is a*x + b*y + c*z + d
 * >= 0 inside, no normalisation needed), in increasing index order (one
 * row). The box test is conservative (a box near a frustum corner may be
 * reported although it misses the frustum, never the reverse). In 2D z = 0.
 */
GEOM_API geom_status geom_octree_frustum(const geom_octree *t, const double planes[24],
                                         geom_neighbors *out);
/**
 * Ordered ray traversal: the items whose box the ray meets within [tmin,
 * tmax] (the conservative slab test of geom_ray_aabb: nothing is missed at a
 * shared face or edge), front to back: sorted by the entry parameter, ties
 * by index; distance[] holds the entry parameter. Nodes are visited front to
 * back by Revelles, Urena and Lastra 2000 (the first child from the entry
 * plane and the midplane parameters, each next one from the current child's
 * exit plane), then any other child the conservative slab test accepts (a
 * ray through an edge or along a midplane), each pruned by its tight
 * bounds. In 2D the ray's z is ignored.
 * Returns GEOM_OK, GEOM_ERR_INVALID_ARG (NULL or NaN ray), GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_octree_ray(const geom_octree *t, const geom_ray *ray, geom_neighbors *out);

/* ======================================= closest point and signed distance */

/** Opaque distance index over a triangle mesh: a SAH BVH plus, per node, the
 *  dipole data of the fast winding number. */
typedef struct geom_meshdist geom_meshdist;

/** Options of geom_meshdist_create; valid when zero-initialised. */
typedef struct geom_meshdist_options {
    uint32_t max_leaf_size;      /**< triangles per BVH leaf; 0 = 4 */
    double beta;                 /**< fast winding number: a node of radius r is
                                      approximated by its dipole beyond beta*r;
                                      0 = 2 (Barill et al.'s default); < 0 = exact
                                      solid-angle sum always */
    double tolerance;            /**< fast winding number: if > 0, a node is
                                      approximated only if its error term is at
                                      most tolerance times its share of the mesh
                                      area, so the error per query is at most
                                      tolerance; 0 = Barill's criterion alone
                                      (faster; the reported bound is then the
                                      sum of the accepted terms, rigorous but
                                      pessimistic). Used by
                                      geom_meshdist_winding only:
                                      geom_meshdist_signed_distance ignores it
                                      (its sign is exact, refined until
                                      decided, so no tolerance applies) */
    int threads;                 /**< 0 = all available; results do not depend on it */
    const geom_allocator *alloc; /**< NULL = malloc */
} geom_meshdist_options;

/**
 * Index the triangle mesh (positions: 3*nv doubles, tris: 3*nt indices;
 * both copied). Degenerate (zero-area) triangles are accepted. Returns
 * GEOM_OK; GEOM_ERR_INVALID_ARG (NULL, index >= nv, NaN/Inf: the diag names
 * the first bad triangle); GEOM_ERR_NOMEM; GEOM_ERR_LIMIT.
 */
GEOM_API geom_status geom_meshdist_create(const double *positions, size_t nv, const uint32_t *tris,
                                          size_t nt, const geom_meshdist_options *opt,
                                          geom_meshdist **out, geom_diag *diag);
/** Free. NULL is a no-op. */
GEOM_API void geom_meshdist_destroy(geom_meshdist *m);
/** The BVH the index traverses (owned by m). */
GEOM_API const geom_bvh *geom_meshdist_bvh(const geom_meshdist *m);
/** Bytes held (BVH, mesh copy and dipole data). */
GEOM_API size_t geom_meshdist_bytes(const geom_meshdist *m);

/**
 * Closest point on the mesh to each of nq query points (3*nq doubles), in
 * parallel over the queries (BVH, nearest child first, pruned by box
 * distance). Per query: point[3q..] the closest point, tri[q] its triangle
 * (ties: the smaller triangle index), bary[3q..] its barycentric coordinates
 * in that triangle (Ericson 2005, 5.1.5: exact 0 on the Voronoi-region
 * boundaries it picks), distance[q] the Euclidean distance. Any output may
 * be NULL. With an empty mesh tri is GEOM_INVALID_INDEX and distance +Inf.
 * Returns GEOM_OK or GEOM_ERR_INVALID_ARG (NULL m/queries, NaN/Inf query:
 * the diag names the first).
 */
GEOM_API geom_status geom_meshdist_closest(const geom_meshdist *m, const double *queries, size_t nq,
                                           double *point, uint32_t *tri, double *bary,
                                           double *distance, int threads, geom_diag *diag);

/**
 * Generalized winding number (Jacobson, Kavan and Sorkine-Hornung 2013) of
 * each query: sum over triangles of the signed solid angle (Van Oosterom and
 * Strackee 1983) over 4*pi, with the fast hierarchical approximation of
 * Barill et al. 2018 (first-order dipole per BVH node beyond beta*r; with a
 * tolerance option, only where that node's error term is within its area
 * share of the tolerance, so the error is at most `tolerance` per query). 1
 * inside a closed outward-oriented mesh, 0 outside, a smooth value for open
 * or self-intersecting meshes. w receives nq doubles. If report is non-NULL
 * it receives, over the queries, the largest (max_error) and mean error
 * bound of the approximation (method GEOM_ERROR_BOUND; 0 when beta < 0):
 * per query the sum over approximated nodes of the smaller of A*r*2 /
 * (4*pi*g^3) (the Taylor remainder of the dipole kernel) and a bound that is
 * small on flat patches, (2*r*D + 2*M) / (4*pi*g^3) + 3*I / (4*pi*g^4),
 * plus rounding; A is the node's triangle area, r its radius, g the larger
 * of R - r (R the query's distance to its centre) and the distance to its
 * box, D the sum of A_t*|n_t - nu| over its triangles (nu its mean normal
 * direction), I the integral of |x - c|^2 over its surface and M the norm of
 * the integral of (x - c) (zero up to rounding); and in
 * `evaluations` the number of exact triangle terms plus dipole terms.
 * Returns as geom_meshdist_closest.
 */
GEOM_API geom_status geom_meshdist_winding(const geom_meshdist *m, const double *queries, size_t nq,
                                           double *w, geom_error_report *report, int threads,
                                           geom_diag *diag);

/**
 * Signed distance: the closest-point distance, negative inside, inside
 * meaning winding number >= 1/2 (exactly 1/2 counts as inside). The sign is
 * that of the exact solid-angle sum: the fast approximation (Barill's
 * criterion; the tolerance option is ignored here) is refined while its
 * error bound straddles 1/2, always opening the approximated node with the
 * largest error term (a node's term uses the larger of R - r and the distance
 * to its box as the distance bound), and a query still undecided with every
 * node open gets the exact sum. sd receives nq doubles; report (may be NULL)
 * as geom_meshdist_winding, max_error being the final bound of each query
 * (a bound on |w - computed w| that excludes 1/2 unless the exact sum
 * decided). Returns as geom_meshdist_closest, or GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_meshdist_signed_distance(const geom_meshdist *m, const double *queries,
                                                   size_t nq, double *sd,
                                                   geom_error_report *report, int threads,
                                                   geom_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_SPATIAL_H */
