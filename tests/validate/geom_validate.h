/*
 * geom_validate: reference answers for libgeom's tests and benchmarks.
 *
 * A thin C interface over C++ reference libraries (CGAL 5.5 today; the
 * OpenSubdiv and SISL parts are added beside it). Only tests and benchmarks
 * link it (target `geom_validate`, built by tests/validate/CMakeLists.txt
 * when the libraries are found); the library itself never depends on it.
 *
 * Every function catches C++ exceptions (CGAL precondition failures,
 * std::bad_alloc, ...) and reports them as GV_ERR_INTERNAL: nothing ever
 * throws across this C interface. Nothing here prints or keeps global state,
 * and every function is reentrant.
 *
 * Parts and their sources:
 *  - exact predicates, barycentric coordinates and ray/triangle
 *    intersection (validate_exact.cpp):
 *    computed exactly (every sum, product and determinant of the double
 *    inputs in CGAL::Gmpzf, exact big floats, through the kernel
 *    CGAL::Simple_cartesian<CGAL::Gmpzf>; quotients as exact GMP rationals),
 *    rounded once, to nearest, at the end;
 *  - polygon soups and meshes (validate_mesh.cpp): CGAL's
 *    Polygon_mesh_processing on a CGAL::Surface_mesh with the kernel
 *    CGAL::Exact_predicates_inexact_constructions_kernel (exact predicates,
 *    constructions in double);
 *  - subdivision surfaces (validate_subdiv_cgal.cpp): CGAL's
 *    Subdivision_method_3 Loop and Catmull-Clark on a CGAL::Surface_mesh
 *    over CGAL::Simple_cartesian<double>.
 */
#ifndef GEOM_VALIDATE_H
#define GEOM_VALIDATE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes of the functions returning int (other than the predicates). */
#define GV_OK 0
#define GV_ERR_DEGENERATE (-1) /**< zero-area triangle / zero-volume tetrahedron */
#define GV_ERR_INVALID (-2)    /**< NULL pointer, NaN/Inf, index out of range, face with < 3 vertices */
#define GV_ERR_INTERNAL (-3)   /**< a C++ exception was caught (out of memory, CGAL failure) */

/** Returned by the sign predicates for NULL or non-finite input, or when an
 *  exception was caught; never a valid sign. */
#define GV_SIGN_ERROR 2

/* ------------------------------------------------------- exact predicates */

/**
 * Exact sign of the 2D orientation det[b-a; c-a] of three points (2 doubles
 * each): 1 if a, b, c are counter-clockwise, -1 if clockwise, 0 if collinear.
 * Same convention as geom_orient2d. GV_SIGN_ERROR for NULL/non-finite input.
 */
int gv_orient2d(const double a[2], const double b[2], const double c[2]);

/**
 * Exact sign of det[a-d; b-d; c-d] for four 3D points (3 doubles each), the
 * convention of geom_orient3d (and Shewchuk's orient3d): 1 when d lies below
 * the plane through a, b, c, with a, b, c counter-clockwise seen from above;
 * -1 above; 0 coplanar. This is the opposite of CGAL::orientation(a,b,c,d),
 * which is what is evaluated (and negated). GV_SIGN_ERROR for bad input.
 */
int gv_orient3d(const double a[3], const double b[3], const double c[3], const double d[3]);

/**
 * Exact in-circle sign, CGAL::side_of_oriented_circle(a,b,c,d) (2 doubles
 * each): the sign of Shewchuk's incircle determinant, the convention of
 * geom_incircle. 1 if d is inside the circle through a, b, c when they are
 * counter-clockwise (outside when clockwise), -1 on the other side, 0 on the
 * circle. GV_SIGN_ERROR for NULL/non-finite input.
 */
int gv_incircle(const double a[2], const double b[2], const double c[2], const double d[2]);

/* ------------------------------------------------ barycentric coordinates */

/*
 * Exact barycentric coordinates rounded to the nearest double (ties to even,
 * subnormals included: the exact rational is rounded once, by MPFR and, below
 * DBL_MIN, by exact integer division; CGAL::Gmpq::to_double is not used, as
 * it truncates). A coordinate that is exactly 0 is returned as +0.0;
 * a nonzero coordinate is never 0 unless its magnitude is below 2^-1075.
 * Return GV_OK, GV_ERR_DEGENERATE (l all 0), GV_ERR_INVALID (NULL or
 * non-finite input; l all 0 when l is not NULL) or GV_ERR_INTERNAL.
 */

/** 2D triangle (a, b, c, p: 2 doubles each; l: 3 doubles):
 *  l[0] = det(p,b,c)/det(a,b,c), l[1] = det(a,p,c)/det(a,b,c),
 *  l[2] = det(a,b,p)/det(a,b,c), either orientation. */
int gv_bary_tri2(const double a[2], const double b[2], const double c[2], const double p[2],
                 double l[3]);

/** 3D triangle (3 doubles each; l: 3 doubles): coordinates of the orthogonal
 *  projection of p onto the triangle's plane, l[i] = (n . n_i) / (n . n) with
 *  n = (b-a) x (c-a), n_0 = (c-b) x (p-b), n_1 = (a-c) x (p-c),
 *  n_2 = (b-a) x (p-a). Degenerate when n = 0 (collinear vertices). */
int gv_bary_tri3(const double a[3], const double b[3], const double c[3], const double p[3],
                 double l[3]);

/** Tetrahedron (3 doubles each; l: 4 doubles): l[i] is the signed volume of
 *  the tetrahedron with vertex i replaced by p over the volume of (a,b,c,d).
 *  Degenerate when a, b, c, d are coplanar. */
int gv_bary_tet(const double a[3], const double b[3], const double c[3], const double d[3],
                const double p[3], double l[4]);

/** The rational num/den of two doubles, rounded once to the nearest double
 *  (the rounding used above; exposed so tests can check it). den == 0 or
 *  non-finite input gives GV_ERR_INVALID and *out = 0. */
int gv_div_rounded(double num, double den, double *out);

/* ------------------------------------------------------ ray / triangle */

/**
 * Exact ray/triangle intersection: CGAL::do_intersect(Ray_3, Triangle_3) in
 * CGAL::Simple_cartesian<CGAL::Gmpzf> (every predicate on the double inputs
 * exact). The ray is o + t d, t >= 0 (the origin included); the triangle is
 * closed (its edges and vertices belong to it); a ray in the triangle's
 * plane that meets it counts as intersecting. Returns 1 (they intersect),
 * 0 (they do not), or GV_SIGN_ERROR for NULL/non-finite input, d = 0, a
 * degenerate (collinear) triangle, or a caught exception.
 */
int gv_ray_triangle(const double o[3], const double d[3], const double a[3], const double b[3],
                    const double c[3]);

/* ------------------------------------------------------- polygon soups */

/*
 * A polygon soup: nverts points (xyz: 3*nverts doubles), nfaces polygons,
 * face i having face_sizes[i] >= 3 corners whose vertex indices are the next
 * face_sizes[i] entries of `indices` (sum(face_sizes) uint32_t in all, each
 * < nverts). Corners are in the order that makes the face counter-clockwise
 * seen from the side its normal points to. A polygon that repeats a vertex
 * index is GV_ERR_INVALID.
 *
 * How the soup becomes a CGAL::Surface_mesh (gv_soup_check and
 * gv_vertex_normals do the same):
 *  1. When CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh()
 *     accepts the soup (every edge used at most twice and in opposite
 *     directions, every vertex a disk or half-disk), it is converted as is.
 *  2. Otherwise CGAL::Polygon_mesh_processing::orient_polygon_soup() first
 *     reverses polygons to make the orientation consistent (each connected
 *     component keeps the orientation of its lowest-numbered polygon) and
 *     duplicates every vertex whose polygons do not form one fan (and the
 *     endpoints of edges used by more than two polygons): the copies are
 *     appended after the nverts input points, each copy taking one fan.
 *  3. polygon_soup_to_polygon_mesh() then adds the points in order, so mesh
 *     vertex i is soup vertex i for every i < nverts (isolated soup vertices
 *     included, as isolated mesh vertices), and mesh vertices >= nverts are
 *     the copies of step 2.
 */

/** What gv_soup_check found. All counts are of the built Surface_mesh. */
typedef struct gv_soup_info {
    /** PMP::is_polygon_soup_a_polygon_mesh() on the input soup: 1 if the
     *  soup is an oriented 2-manifold (possibly with boundary) as given. */
    int is_polygon_soup_a_polygon_mesh;
    /** Step 2 (orient_polygon_soup) was run: 1 when is_polygon_soup_a_polygon_mesh == 0. */
    int reoriented;
    size_t reversed_faces;      /**< polygons orient_polygon_soup reversed */
    size_t duplicated_vertices; /**< vertex copies it appended */
    /** CGAL::is_valid_polygon_mesh() on the built mesh (1/0). Note that
     *  CGAL 5.5 counts a mesh with an isolated vertex as invalid (its
     *  is_valid_halfedge_graph wants a halfedge at every vertex). */
    int valid;
    /** CGAL::is_closed(): no border halfedge (1/0). */
    int closed;
    size_t vertices;          /**< V, isolated vertices and copies included */
    size_t edges;             /**< E */
    size_t faces;             /**< F */
    size_t isolated_vertices; /**< vertices with no incident face */
    /** Face-connected components (PMP::connected_components); isolated
     *  vertices are not components. */
    size_t components;
    /** Boundary loops (PMP::extract_boundary_cycles). */
    size_t border_cycles;
    /** V - E + F of the whole built mesh (isolated vertices count 1 each). */
    long long euler_characteristic;
    /** Sum over the face-connected components c of
     *  (2 - chi_c - b_c) / 2, with chi_c = V_c - E_c + F_c and b_c the
     *  boundary loops of c (for a closed component (2 - chi_c) / 2). The
     *  built mesh is orientable, so every term is an integer. */
    long long genus;
    /** PMP::does_self_intersect() on a copy whose faces were triangulated
     *  (PMP::triangulate_faces) when they are not all triangles: 1 if two
     *  faces intersect other than along their shared edge or vertex, 0 if
     *  not, -1 if the triangulation failed. A degenerate (zero-area)
     *  triangle counts as self-intersecting. Note that the copies made in
     *  step 2 touch their originals, so a soup with non-manifold vertices or
     *  edges counts as self-intersecting. */
    int self_intersecting;
} gv_soup_info;

/**
 * Check a polygon soup with CGAL (see above for how it is turned into a
 * mesh) and fill *out. Returns GV_OK, GV_ERR_INVALID (NULL pointer with
 * nonzero count, index >= nverts, face size < 3, repeated vertex in a face,
 * non-finite coordinate; *out is then zeroed) or GV_ERR_INTERNAL.
 */
int gv_soup_check(size_t nverts, const double *xyz, size_t nfaces, const uint32_t *face_sizes,
                  const uint32_t *indices, gv_soup_info *out);

/* How vertex normals are weighted. */
#define GV_NORMALS_CGAL 0       /**< CGAL 5.5's default, described below */
#define GV_NORMALS_SINE 1       /**< CGAL's sine-weighted sum only */
#define GV_NORMALS_UNWEIGHTED 2 /**< sum of unit face normals only */

/**
 * Unit vertex normals of the soup by
 * CGAL::Polygon_mesh_processing::compute_vertex_normals() on the built
 * Surface_mesh; normals receives 3*nverts doubles in the soup's vertex order.
 *
 * What CGAL 5.5.1 computes (compute_normal.h, read for this):
 *  - face normal: the sum over the fan triangles (p0, p_k, p_k+1) of the
 *    face of (p_k+1 - p_k) x (p0 - p_k) / 2, normalised (for a planar
 *    polygon, the area vector's direction, as Newell's method);
 *  - vertex normal: NOT an area- or angle-weighted average. CGAL first looks
 *    for the "most visible" normal (Aubry et al., "On the most 'normal'
 *    normal", 2008): the direction maximising the smallest dot product with
 *    the unit normals of the incident faces, i.e. the centre of the smallest
 *    spherical cap holding them, searched among the sums of pairs and the
 *    circumcentres of triples of face normals, with a fixed 0.01 degree
 *    tolerance in its comparisons. A vertex with one face gets that face's
 *    normal. Only when no such normal is found (the face normals do not fit
 *    in an open hemisphere, e.g. at a fold or a saddle with opposite faces)
 *    does it fall back to the sine-weighted sum: for each incident face,
 *    (e2 x e1) / (|e1| |e2|) where e1, e2 go from v to its previous and next
 *    corners in that face, i.e. the corner's plane normal times the sine of
 *    the corner angle; if some |e1||e2| is 0, to the plain sum of unit face
 *    normals. The result is normalised; a vertex with no face, or whose sum
 *    is exactly zero, gets (0, 0, 0).
 *  weighting selects GV_NORMALS_CGAL (the above, what compute_vertex_normals
 *  does), GV_NORMALS_SINE (only its sine-weighted fallback, for every vertex)
 *  or GV_NORMALS_UNWEIGHTED (only the plain sum of unit face normals). For
 *  a vertex whose faces all have the same normal, all three agree, and any
 *  area- or angle-weighted average agrees with them.
 *
 * Vertex mapping: soup vertex i gets the normal of mesh vertex i. When the
 * soup is a polygon mesh as given, that is all of vertex i's faces with the
 * given orientation. Otherwise (see step 2 above) faces may have been
 * reversed, and at a non-manifold vertex only the fan that kept index i
 * contributes (the copies' normals are dropped); *ncopies (may be NULL)
 * receives the number of copies made, so a caller can restrict comparisons
 * to soups where it is 0.
 *
 * Returns GV_OK, GV_ERR_INVALID (as gv_soup_check, or NULL normals, or an
 * unknown weighting) or GV_ERR_INTERNAL; normals are zeroed on error.
 */
int gv_vertex_normals(size_t nverts, const double *xyz, size_t nfaces, const uint32_t *face_sizes,
                      const uint32_t *indices, int weighting, double *normals, size_t *ncopies);

/* ------------------------------------------------------------ subdivision */

/*
 * CGAL's subdivision surfaces (validate_subdiv_cgal.cpp):
 * CGAL::Subdivision_method_3::Loop_subdivision and CatmullClark_subdivision
 * with CGAL::parameters::number_of_iterations(levels), on a
 * CGAL::Surface_mesh over CGAL::Simple_cartesian<double> (every weight and
 * sum in double). What CGAL 5.5 computes (subdivision_masks_3.h, read for
 * this); interior rules only matter for the closed meshes this is meant for:
 *  - Loop (triangles; 1-to-4 split): edge point (3 (p1 + p2) + f1 + f2) / 8
 *    over the two opposite vertices; vertex point of valence n:
 *    (1 - C_n) v + (C_n / n) sum(neighbours), C_n = 5/8 - (3 + 2 cos(2 pi /
 *    n))^2 / 64 = 5/8 - (3/8 + cos(2 pi / n) / 4)^2, i.e. Loop's original
 *    weights (beta = C_n / n; 3/16 at n = 3 and 1/16 at n = 6, where Warren's
 *    simplified weights coincide), with n = 6 special-cased as (10 v +
 *    sum) / 16. These are OpenSubdiv's (Sdc::Scheme<SCHEME_LOOP>) weights.
 *  - Catmull-Clark (any polygons; quads out): face point = centroid; edge
 *    point = (p1 + p2 + f1 + f2) / 4; vertex point = (Q + 2 R + (n - 3) v)
 *    / n with Q the mean of the n adjacent face points and R the mean of the
 *    n edge midpoints: the original Catmull-Clark rule, OpenSubdiv's too.
 *  - boundary edges (not what this is validated on): midpoints, and
 *    vertices (p- + 6 v + p+) / 8 for both schemes (OpenSubdiv's "edge
 *    only" crease rule); no creases or corners.
 * The arithmetic order differs from OpenSubdiv's, so results agree with it
 * (and libgeom) to rounding, not to the bit.
 */

/** Schemes of gv_subdiv_cgal. */
#define GV_SUBDIV_LOOP 0
#define GV_SUBDIV_CATMULL_CLARK 1
/** Most levels gv_subdiv_cgal accepts (faces grow 4 times per level). */
#define GV_SUBDIV_MAX_LEVELS 8

/** A refined mesh from gv_subdiv_cgal; free with gv_subdiv_result_free. */
typedef struct gv_subdiv_result {
    size_t nverts;        /**< refined vertices */
    double *xyz;          /**< 3 * nverts coordinates */
    size_t nfaces;        /**< refined faces */
    uint32_t *face_sizes; /**< nfaces sizes (3 for Loop, 4 for Catmull-Clark) */
    size_t nindices;      /**< sum of face_sizes */
    uint32_t *indices;    /**< vertex indices of each face in turn, CGAL's orientation */
} gv_subdiv_result;

/**
 * Refine the polygon mesh (nverts vertices, 3 doubles each; nfaces faces of
 * face_sizes[i] vertices listed one face after another in indices) `levels`
 * times (0..GV_SUBDIV_MAX_LEVELS) with CGAL's scheme (GV_SUBDIV_LOOP or
 * GV_SUBDIV_CATMULL_CLARK; rules above) and fill *out with the refined
 * vertices and faces, numbered in CGAL's iteration order (NOT OpenSubdiv's:
 * compare positions as sets). The faces must make an oriented 2-manifold
 * (with or without boundary) that CGAL::Surface_mesh::add_face accepts in
 * the given order. Returns GV_OK, GV_ERR_INVALID (NULL pointer, no vertex or
 * face, unknown scheme, bad levels, non-finite coordinate, index out of
 * range, face of fewer than 3 vertices, non-triangle for Loop, a face
 * add_face refuses) or GV_ERR_INTERNAL (an exception, out of memory); *out
 * is zeroed on error.
 */
int gv_subdiv_cgal(int scheme, int levels, size_t nverts, const double *xyz, size_t nfaces,
                   const uint32_t *face_sizes, const uint32_t *indices, gv_subdiv_result *out);

/** Free the buffers of a gv_subdiv_result and zero it; NULL is a no-op. */
void gv_subdiv_result_free(gv_subdiv_result *r);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_VALIDATE_H */
