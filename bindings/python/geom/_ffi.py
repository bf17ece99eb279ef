"""cffi declarations of libgeom's C ABI and the loaded library (ABI mode).

The declarations below are copied from the public headers
(libgeom/include/geom/<module>.h) with comments removed, one dictionary entry
per module, so that no C compiler is needed at import time: ``ffi.dlopen``
loads the shared library built by CMake. ``tests/test_abi.py`` parses the
headers and checks that every declaration here is still identical to the
header's (functions, structs and enums) and that every function is exported
by the loaded library, so drift between the headers and these bindings is
caught by the test suite.

The library is looked up, first match wins:
  1. the path in the environment variable GEOM_LIBRARY (an error if it does
     not load: a wrong explicit path is never silently replaced);
  2. libgeom.so (or .so.0, .dylib, geom.dll) next to this file, for a
     package installed together with its library (pip install
     bindings/python builds and bundles it);
  3. the library named in _libpath.py, which `cmake --install` writes next
     to this file;
  4. the system loader: ctypes.util.find_library("geom"), then
     "libgeom.so.0".
"""

import ctypes.util
import os

import cffi

#: Values of the header macros used as array sizes in the declarations.
MACROS = {
    "GEOM_DIAG_MESSAGE_MAX": 256,
    "GEOM_MESH_REPORT_FIRST": 8,
}

#: Modules in dependency order (as GEOM_ALL_MODULES).
MODULE_ORDER = ("core", "bary", "mesh", "meshio", "spatial", "curve", "surface", "step", "subdiv",
                "implicit", "iso", "ray", "scene")

CDEFS = {
    "core": """
typedef enum geom_status {
    GEOM_OK = 0,
    GEOM_ERR_NOMEM = -1,
    GEOM_ERR_INVALID_ARG = -2,
    GEOM_ERR_PARSE = -3,
    GEOM_ERR_IO = -4,
    GEOM_ERR_DEGENERATE = -5,
    GEOM_ERR_NONMANIFOLD = -6,
    GEOM_ERR_DOMAIN = -7,
    GEOM_ERR_LIMIT = -8
} geom_status;
const char *geom_version_string(void);
const char *geom_status_str(geom_status s);
typedef enum geom_diag_hint {
    GEOM_DIAG_HINT_NONE = 0,
    GEOM_DIAG_HINT_SKIP_INVALID_FACES = 1
} geom_diag_hint;
typedef struct geom_diag {
    geom_status status;
    char message[GEOM_DIAG_MESSAGE_MAX];
    char source[GEOM_DIAG_MESSAGE_MAX];
    size_t line;
    size_t column;
    uint64_t byte_offset;
    geom_diag_hint hint;
} geom_diag;
void geom_diag_clear(geom_diag *d);
size_t geom_diag_format(const geom_diag *d, char *buf, size_t size);
typedef struct geom_allocator {
    void *(*alloc_fn)(void *user, size_t size);
    void *(*realloc_fn)(void *user, void *ptr, size_t old_size, size_t new_size);
    void (*free_fn)(void *user, void *ptr, size_t size);
    void *user;
} geom_allocator;
typedef struct geom_error_report {
    double max_error;
    double mean_error;
    int method;
    size_t evaluations;
    double tolerance;
    size_t pieces;
    double seconds;
} geom_error_report;
typedef struct geom_vec2 {
    double x, y;
} geom_vec2;
typedef struct geom_vec3 {
    double x, y, z;
} geom_vec3;
typedef struct geom_vec4 {
    double x, y, z, w;
} geom_vec4;
typedef struct geom_mat3 {
    double m[9];
} geom_mat3;
typedef struct geom_mat4 {
    double m[16];
} geom_mat4;
geom_mat4 geom_mat4_identity(void);
geom_mat4 geom_mat4_mul(geom_mat4 a, geom_mat4 b);
geom_mat4 geom_mat4_transpose(geom_mat4 a);
double geom_mat4_determinant(geom_mat4 a);
geom_status geom_mat4_inverse(geom_mat4 a, geom_mat4 *out);
geom_status geom_mat4_normal_matrix(geom_mat4 a, geom_mat3 *out);
geom_mat4 geom_mat4_translate(geom_vec3 t);
geom_mat4 geom_mat4_scale(geom_vec3 s);
geom_status geom_mat4_rotate(geom_vec3 axis, double radians, geom_mat4 *out);
geom_status geom_mat4_transform_point(geom_mat4 a, geom_vec3 p, geom_vec3 *out);
geom_status geom_mat4_lookat(geom_vec3 eye, geom_vec3 center, geom_vec3 up, geom_mat4 *out);
geom_status geom_mat4_perspective(double fovy_radians, double aspect, double near_z, double
    far_z, geom_mat4 *out);
geom_status geom_mat4_ortho(double left, double right, double bottom, double top, double near_z,
    double far_z, geom_mat4 *out);
double geom_orient2d(const double a[2], const double b[2], const double c[2]);
double geom_orient3d(const double a[3], const double b[3], const double c[3], const double
    d[3]);
double geom_incircle(const double a[2], const double b[2], const double c[2], const double
    d[2]);
double geom_orient2d_exact(const double a[2], const double b[2], const double c[2]);
double geom_orient3d_exact(const double a[3], const double b[3], const double c[3], const double
    d[3]);
typedef enum geom_predicate {
    GEOM_PREDICATE_ORIENT2D = 1,
    GEOM_PREDICATE_ORIENT3D = 2,
    GEOM_PREDICATE_INCIRCLE = 3,
    GEOM_PREDICATE_ORIENT2D_EXACT = 4,
    GEOM_PREDICATE_ORIENT3D_EXACT = 5
} geom_predicate;
geom_status geom_predicate_many(geom_predicate kind, size_t n, const double *const pts[4],
    const size_t strides[4], double *out);
typedef struct geom_aabb {
    geom_vec3 min;
    geom_vec3 max;
} geom_aabb;
typedef struct geom_ray {
    geom_vec3 origin;
    geom_vec3 dir;
    double tmin;
    double tmax;
} geom_ray;
typedef struct geom_output {
    int fd;
    char *temporary;
    char *impl_path, *impl_dest;
    size_t impl_path_size, impl_dest_size, impl_tmp_size;
    const geom_allocator *impl_alloc;
} geom_output;
geom_status geom_output_open(const char *path, const geom_allocator *alloc,
                                      geom_output *out, geom_diag *diag);
geom_status geom_output_write(geom_output *out, const void *data, size_t n,
                                       geom_diag *diag);
geom_status geom_output_commit(geom_output *out, geom_diag *diag);
void geom_output_abort(geom_output *out);
""",
    "bary": """
geom_status geom_bary_tri2(const double a[2], const double b[2], const double c[2], const double
    p[2], double l[3]);
geom_status geom_bary_tri3(const double a[3], const double b[3], const double c[3], const double
    p[3], double l[3]);
geom_status geom_bary_tet(const double a[3], const double b[3], const double c[3], const double
    d[3], const double p[3], double l[4]);
geom_status geom_bary_mean_value(size_t n, const double *poly, const double p[2], double *w);
geom_status geom_bary_wachspress(size_t n, const double *poly, const double p[2], double *w);
geom_status geom_bary_interpolate(size_t k, const double *l, size_t ncomp, const double *attr,
    double *out);
geom_status geom_bary_perspective(const double l[3], const double w[3], double lp[3]);
typedef enum geom_bary_simplex {
    GEOM_BARY_TRI2 = 1,
    GEOM_BARY_TRI3 = 2,
    GEOM_BARY_TET = 3
} geom_bary_simplex;
geom_status geom_bary_simplex_many(geom_bary_simplex kind, size_t n,
                                            const double *const pts[5], const size_t strides[5],
                                            double *out, int32_t *status, size_t *n_failed);
geom_status geom_bary_polygon_many(int wachspress, size_t nv, const double *poly,
                                            size_t n, const double *p, double *w,
                                            int32_t *status, size_t *n_failed);
geom_status geom_bary_perspective_many(size_t n, const double *l, size_t sl, const double *w,
    size_t sw, double *lp, int32_t *status, size_t *n_failed);
geom_status geom_bary_interpolate_many(size_t n, size_t k, const double *l, size_t ncomp,
    const double *attr, double *out);
""",
    "mesh": """
typedef struct geom_mesh geom_mesh;
geom_mesh *geom_mesh_create(const geom_allocator *alloc);
void geom_mesh_destroy(geom_mesh *m);
geom_status geom_mesh_clone(const geom_mesh *m, geom_mesh **out);
size_t geom_mesh_n_vertices(const geom_mesh *m);
size_t geom_mesh_n_halfedges(const geom_mesh *m);
size_t geom_mesh_n_edges(const geom_mesh *m);
size_t geom_mesh_n_faces(const geom_mesh *m);
size_t geom_mesh_n_live_vertices(const geom_mesh *m);
size_t geom_mesh_n_live_edges(const geom_mesh *m);
size_t geom_mesh_n_live_faces(const geom_mesh *m);
uint32_t geom_mesh_he_next(const geom_mesh *m, uint32_t h);
uint32_t geom_mesh_he_vertex(const geom_mesh *m, uint32_t h);
uint32_t geom_mesh_he_face(const geom_mesh *m, uint32_t h);
uint32_t geom_mesh_face_he(const geom_mesh *m, uint32_t f);
bool geom_mesh_face_is_deleted(const geom_mesh *m, uint32_t f);
size_t geom_mesh_face_valence(const geom_mesh *m, uint32_t f);
typedef enum geom_mesh_domain {
    GEOM_MESH_DOMAIN_VERTEX = 0,
    GEOM_MESH_DOMAIN_FACE = 1,
    GEOM_MESH_DOMAIN_EDGE = 2,
    GEOM_MESH_DOMAIN_CORNER = 3
} geom_mesh_domain;
typedef struct geom_mesh_build_channel {
    const char *name;
    geom_mesh_domain domain;
    size_t ncomp;
    size_t n_values;
    const double *values;
    const uint32_t *indices;
} geom_mesh_build_channel;
typedef struct geom_mesh_build_options {
    int skip_invalid_faces;
    int keep_orientation;
    int trusted;
    const geom_mesh_build_channel *channels;
    size_t n_channels;
} geom_mesh_build_options;
typedef struct geom_mesh_build_report {
    size_t invalid_faces;
    uint32_t first_invalid_faces[GEOM_MESH_REPORT_FIRST];
    size_t flipped_faces;
    uint32_t first_flipped_faces[GEOM_MESH_REPORT_FIRST];
    size_t nonmanifold_edges;
    uint32_t first_nonmanifold_faces[GEOM_MESH_REPORT_FIRST];
    size_t detached_faces;
    uint32_t first_detached_faces[GEOM_MESH_REPORT_FIRST];
    size_t split_vertices;
    uint32_t first_split_vertices[GEOM_MESH_REPORT_FIRST];
    size_t added_vertices;
    size_t isolated_vertices;
    size_t nonorientable_components;
} geom_mesh_build_report;
geom_status geom_mesh_build(geom_mesh *m, size_t nverts, const double *xyz, size_t nfaces, const
    uint32_t *face_sizes, const uint32_t *indices, const geom_mesh_build_options *opt,
    geom_mesh_build_report *report, geom_diag *diag);
const uint32_t *geom_mesh_vertex_origin(const geom_mesh *m);
const uint32_t *geom_mesh_face_origin(const geom_mesh *m);
geom_status geom_mesh_to_soup(const geom_mesh *m, uint32_t *face_sizes, uint32_t *indices,
    size_t *n_indices);
size_t geom_mesh_channel_count(const geom_mesh *m);
geom_status geom_mesh_channel_add(geom_mesh *m, const char *name, geom_mesh_domain domain,
    size_t ncomp, uint32_t *id);
uint32_t geom_mesh_channel_find(const geom_mesh *m, const char *name, geom_mesh_domain domain);
geom_status geom_mesh_channel_remove(geom_mesh *m, uint32_t id);
const char *geom_mesh_channel_name(const geom_mesh *m, uint32_t id);
geom_mesh_domain geom_mesh_channel_domain(const geom_mesh *m, uint32_t id);
size_t geom_mesh_channel_ncomp(const geom_mesh *m, uint32_t id);
size_t geom_mesh_channel_size(const geom_mesh *m, uint32_t id);
double *geom_mesh_channel_data(geom_mesh *m, uint32_t id);
const double *geom_mesh_channel_cdata(const geom_mesh *m, uint32_t id);
geom_status geom_mesh_corner_pool_resize(geom_mesh *m, uint32_t id, size_t n);
uint32_t *geom_mesh_corner_indices(geom_mesh *m, uint32_t id);
const uint32_t *geom_mesh_corner_cindices(const geom_mesh *m, uint32_t id);
double *geom_mesh_positions(geom_mesh *m);
const double *geom_mesh_cpositions(const geom_mesh *m);
size_t geom_mesh_tag_count(const geom_mesh *m);
size_t geom_mesh_group_count(const geom_mesh *m);
size_t geom_mesh_polyline_count(const geom_mesh *m);
geom_status geom_mesh_polyline_get(const geom_mesh *m, size_t i, size_t *n, const uint32_t
    **verts);
geom_aabb geom_mesh_bbox(const geom_mesh *m);
geom_status geom_mesh_boundary_loops(const geom_mesh *m, size_t *n_loops, uint32_t
    *loop_of_halfedge);
geom_status geom_mesh_components(const geom_mesh *m, size_t *n, uint32_t *vertex_component,
    uint32_t *face_component);
typedef struct geom_mesh_topology {
    size_t vertices, edges, faces;
    size_t boundary_loops;
    size_t components;
    long euler;
    long genus;
    bool manifold;
    bool closed;
    size_t degenerate_faces;
    size_t isolated_vertices;
} geom_mesh_topology;
geom_status geom_mesh_topology_summary(const geom_mesh *m, geom_mesh_topology *t);
typedef enum geom_mesh_defect_kind {
    GEOM_MESH_DEFECT_BAD_INDEX = 1,
    GEOM_MESH_DEFECT_NEXT_PREV = 2,
    GEOM_MESH_DEFECT_FACE_CYCLE = 3,
    GEOM_MESH_DEFECT_VERTEX_HALFEDGE = 4,
    GEOM_MESH_DEFECT_BOUNDARY_NOT_FIRST = 5,
    GEOM_MESH_DEFECT_NONMANIFOLD_VERTEX = 6,
    GEOM_MESH_DEFECT_DELETED_REFERENCE = 7,
    GEOM_MESH_DEFECT_SMALL_FACE = 8,
    GEOM_MESH_DEFECT_CHANNEL = 9
} geom_mesh_defect_kind;
typedef struct geom_mesh_defect {
    geom_mesh_defect_kind kind;
    uint32_t element;
} geom_mesh_defect;
geom_status geom_mesh_validate(const geom_mesh *m, geom_mesh_defect *defects, size_t
    max_defects, size_t *n_defects);
geom_status geom_polygon_triangulate(size_t n, const double *pts, uint32_t *tris);
geom_status geom_mesh_triangulate(geom_mesh *m, size_t *n_new_faces);
geom_status geom_mesh_face_normal(const geom_mesh *m, uint32_t f, double out[3]);
typedef enum geom_normal_weight {
    GEOM_NORMAL_WEIGHT_ANGLE = 0,
    GEOM_NORMAL_WEIGHT_UNIFORM = 1,
    GEOM_NORMAL_WEIGHT_AREA = 2,
    GEOM_NORMAL_WEIGHT_MAX = 3
} geom_normal_weight;
geom_status geom_mesh_vertex_normals(const geom_mesh *m, geom_normal_weight weight, double
    *normals, size_t *n_zero);
typedef struct geom_corner_normal_options {
    geom_normal_weight weight;
    double crease_degrees;
    uint32_t split_at_channel_plus_one;
} geom_corner_normal_options;
geom_status geom_mesh_corner_normals(geom_mesh *m, const geom_corner_normal_options *opt,
    uint32_t *id);
geom_status geom_mesh_tangents(geom_mesh *m, uint32_t *id);
typedef struct geom_uv_report {
    size_t charts;
    size_t seam_edges;
    size_t flipped_faces;
    size_t degenerate_uv_faces;
    double uv_area;
    double uv_min[2], uv_max[2];
} geom_uv_report;
geom_status geom_mesh_uv_data(const geom_mesh *m, uint32_t uv_channel, geom_uv_report *report,
    double *chart_bounds, uint32_t *face_chart, uint8_t *seam_edge);
typedef enum geom_feature_kind {
    GEOM_FEATURE_BOUNDARY = 1,
    GEOM_FEATURE_CREASE = 2,
    GEOM_FEATURE_SILHOUETTE = 4
} geom_feature_kind;
typedef struct geom_feature_options {
    unsigned kinds;
    double crease_degrees;
    double eye[3];
} geom_feature_options;
geom_status geom_mesh_features(geom_mesh *m, const geom_feature_options *opt, uint8_t
    *edge_kind, size_t *n_polylines);
typedef struct geom_clip_options {
    int cap;
} geom_clip_options;
geom_status geom_mesh_clip_plane(const geom_mesh *m, const double plane[4], const
    geom_clip_options *opt, geom_mesh **out);
geom_status geom_mesh_clip_frustum(const geom_mesh *m, geom_mat4 view_proj, const
    geom_clip_options *opt, geom_mesh **out);
typedef enum geom_mesh_circ_kind {
    GEOM_MESH_CIRC_VERTEX_OUTGOING = 0,
    GEOM_MESH_CIRC_VERTEX_FACES = 1,
    GEOM_MESH_CIRC_VERTEX_VERTICES = 2,
    GEOM_MESH_CIRC_FACE_HALFEDGES = 3,
    GEOM_MESH_CIRC_FACE_VERTICES = 4
} geom_mesh_circ_kind;
typedef struct geom_mesh_circ {
    const geom_mesh *mesh;
    geom_mesh_circ_kind kind;
    uint32_t start;
    uint32_t current;
    int active;
} geom_mesh_circ;
geom_mesh_circ geom_mesh_circ_begin(const geom_mesh *m, geom_mesh_circ_kind kind, uint32_t elem);
bool geom_mesh_circ_next(geom_mesh_circ *c, uint32_t *out);
geom_status geom_mesh_halfedge_arrays(const geom_mesh *m, uint32_t *next, uint32_t *prev,
                                               uint32_t *vertex, uint32_t *face);
geom_status geom_mesh_vertex_rings(const geom_mesh *m, geom_mesh_circ_kind kind,
                                            size_t *offsets, uint32_t *items, size_t capacity,
                                            size_t *count);
geom_status geom_mesh_add_vertex(geom_mesh *m, const double p[3], uint32_t *out);
geom_status geom_mesh_add_face(geom_mesh *m, size_t n, const uint32_t *verts, uint32_t *out);
void geom_mesh_clear(geom_mesh *m);
geom_status geom_mesh_compact(geom_mesh *m, uint32_t *vertex_map, uint32_t *face_map);
geom_status geom_mesh_delete_face(geom_mesh *m, uint32_t f);
geom_status geom_mesh_delete_vertex(geom_mesh *m, uint32_t v);
uint32_t geom_mesh_find_edge(const geom_mesh *m, uint32_t a, uint32_t b);
uint32_t geom_mesh_find_halfedge(const geom_mesh *m, uint32_t a, uint32_t b);
geom_status geom_mesh_polyline_add(geom_mesh *m, size_t n, const uint32_t *verts);
geom_status geom_mesh_mtllib_add(geom_mesh *m, const char *name);
size_t geom_mesh_mtllib_count(const geom_mesh *m);
const char *geom_mesh_mtllib_get(const geom_mesh *m, size_t i);
typedef struct geom_mesh_tag {
    const char *name;
    size_t nint, nfloat, nstring;
    const int64_t *ints;
    const double *floats;
    const char *const *strings;
} geom_mesh_tag;
geom_status geom_mesh_tag_get(const geom_mesh *m, size_t i, geom_mesh_tag *out);
geom_status geom_mesh_tag_add(geom_mesh *m, const geom_mesh_tag *tag);
typedef struct geom_mesh_group {
    const char *group;
    const char *object;
    const char *material;
    const char *smoothing;
} geom_mesh_group;
geom_status geom_mesh_group_get(const geom_mesh *m, size_t i, geom_mesh_group *out);
geom_status geom_mesh_group_add(geom_mesh *m, const geom_mesh_group *g, uint32_t *id);
uint32_t *geom_mesh_face_groups(geom_mesh *m);
const uint32_t *geom_mesh_face_cgroups(const geom_mesh *m);
size_t geom_mesh_vertex_valence(const geom_mesh *m, uint32_t v);
bool geom_mesh_face_is_degenerate(const geom_mesh *m, uint32_t f);
bool geom_mesh_vertex_is_deleted(const geom_mesh *m, uint32_t v);
bool geom_mesh_edge_is_deleted(const geom_mesh *m, uint32_t e);
""",
    "meshio": """
typedef enum geom_meshio_format {
    GEOM_MESHIO_FORMAT_AUTO = 0,
    GEOM_MESHIO_FORMAT_OBJ = 1,
    GEOM_MESHIO_FORMAT_OFF = 2,
    GEOM_MESHIO_FORMAT_PLY = 3,
    GEOM_MESHIO_FORMAT_STL = 4,
    GEOM_MESHIO_FORMAT_GLB = 5
} geom_meshio_format;
geom_meshio_format geom_meshio_format_from_name(const char *name);
const char *geom_meshio_format_name(geom_meshio_format format);
typedef struct geom_meshio_read_stats {
    geom_meshio_format format;
    int binary;
    size_t skipped_statements;
    char first_skipped[32];
    size_t skipped_elements;
    size_t skipped_properties;
    size_t welded_corners;
    size_t input_vertices;
    size_t input_faces;
} geom_meshio_read_stats;
typedef struct geom_meshio_read_options {
    geom_meshio_format format;
    geom_mesh_build_options build;
    size_t max_elements;
    const geom_allocator *alloc;
    geom_meshio_read_stats *stats;
    int gltf_z_up;
} geom_meshio_read_options;
geom_status geom_meshio_read(const char *path, const geom_meshio_read_options *opt, geom_mesh
    **out, geom_mesh_build_report *report, geom_diag *diag);
geom_status geom_meshio_read_memory(const void *data, size_t size, const char *source_name,
    const geom_meshio_read_options *opt, geom_mesh **out, geom_mesh_build_report *report,
    geom_diag *diag);
typedef enum geom_meshio_encoding {
    GEOM_MESHIO_ENCODING_DEFAULT = 0,
    GEOM_MESHIO_ENCODING_ASCII = 1,
    GEOM_MESHIO_ENCODING_BINARY_LE = 2,
    GEOM_MESHIO_ENCODING_BINARY_BE = 3
} geom_meshio_encoding;
typedef struct geom_meshio_write_options {
    geom_meshio_format format;
    geom_meshio_encoding encoding;
    unsigned omit;
    int precision;
    int ply_float;
    int gltf_keep_v;
    int gltf_z_up;
    const geom_allocator *alloc;
} geom_meshio_write_options;
geom_status geom_meshio_write(const geom_mesh *m, const char *path, const
    geom_meshio_write_options *opt, geom_diag *diag);
geom_status geom_meshio_write_memory(const geom_mesh *m, const geom_meshio_write_options *opt,
    void **data, size_t *size, geom_diag *diag);
typedef geom_status (*geom_meshio_write_fn)(void *user, const void *data, size_t size);
geom_status geom_meshio_write_stream(const geom_mesh *m, const geom_meshio_write_options *opt,
    geom_meshio_write_fn fn, void *user, geom_diag *diag);
typedef struct geom_meshio_soup {
    size_t n_vertices;
    const double *xyz;
    const double *normals;
    size_t n_faces;
    const uint32_t *face_sizes;
    const uint32_t *indices;
} geom_meshio_soup;
geom_status geom_meshio_write_soup(const geom_meshio_soup *s, const char *path,
    const geom_meshio_write_options *opt, geom_diag *diag);
geom_status geom_meshio_write_soup_stream(const geom_meshio_soup *s,
    const geom_meshio_write_options *opt, geom_meshio_write_fn fn, void *user, geom_diag *diag);
geom_status geom_meshio_write_soup_part(const geom_meshio_soup *s, size_t first_vertex,
    int header, const geom_meshio_write_options *opt, geom_meshio_write_fn fn, void *user,
    geom_diag *diag);
void geom_meshio_buffer_free(void *data, size_t size, const geom_allocator *alloc);
geom_meshio_format geom_meshio_format_sniff(const void *data, size_t size);
""",
    "curve": """
typedef struct geom_nurbs_curve {
    int degree;
    size_t n;
    size_t dim;
    const double *knots;
    const double *points;
    const double *weights;
} geom_nurbs_curve;
geom_status geom_curve_bezier_eval(int degree, size_t dim, const double *ctrl, double t, double
    *out);
geom_status geom_curve_bezier_derivs(int degree, size_t dim, const double *ctrl, double t, int
    nderiv, double *ders);
typedef enum geom_knot_kind {
    GEOM_KNOTS_CLAMPED = 0,
    GEOM_KNOTS_UNCLAMPED = 1,
    GEOM_KNOTS_PERIODIC = 2
} geom_knot_kind;
geom_status geom_curve_bspline_uniform_knots(geom_knot_kind kind, int degree, size_t n, double
    *knots);
geom_status geom_curve_nurbs_validate(const geom_nurbs_curve *c, size_t nknots, geom_diag
    *diag);
geom_status geom_curve_nurbs_domain(const geom_nurbs_curve *c, double *u0, double *u1);
geom_status geom_curve_nurbs_eval(const geom_nurbs_curve *c, double u, unsigned flags, double
    *out);
geom_status geom_curve_nurbs_derivs(const geom_nurbs_curve *c, double u, int nderiv, unsigned
    flags, double *ders);
geom_status geom_curve_nurbs_curvature(const geom_nurbs_curve *c, double u, unsigned flags,
    double *curvature, double *torsion);
geom_status geom_curve_nurbs_insert_knot(const geom_nurbs_curve *c, double u, size_t times,
    double *knots, double *points, double *weights, geom_nurbs_curve *out, geom_diag *diag);
geom_status geom_curve_nurbs_elevate_bound(const geom_nurbs_curve *c, int times, size_t *n,
    size_t *nknots);
geom_status geom_curve_nurbs_elevate(const geom_nurbs_curve *c, int times, double *knots, double
    *points, double *weights, geom_nurbs_curve *out, geom_diag *diag);
geom_status geom_curve_nurbs_arc_bound(double start, double end, size_t *n, size_t *nknots);
geom_status geom_curve_nurbs_arc(size_t dim, const double *center, const double *xaxis, const
    double *yaxis, double radius, double start, double end, double *knots, double *points,
    double *weights, geom_nurbs_curve *out, geom_diag *diag);
geom_status geom_curve_nurbs_circle(size_t dim, const double *center, const double *xaxis, const
    double *yaxis, double radius, double *knots, double *points, double *weights,
    geom_nurbs_curve *out, geom_diag *diag);
geom_status geom_curve_nurbs_arc_length(const geom_nurbs_curve *c, double u0, double u1, double
    rel_tol, double *length, geom_error_report *report, geom_diag *diag);
geom_status geom_curve_nurbs_closest_point(const geom_nurbs_curve *c, const double *q, double
    *u, double *point, double *distance, geom_diag *diag);
typedef struct geom_curve_polyline_options {
    double tolerance;
    int method;
    size_t max_points;
} geom_curve_polyline_options;
geom_status geom_curve_nurbs_polyline(const geom_nurbs_curve *c, const
    geom_curve_polyline_options *options, double *params, double *points, size_t capacity,
    size_t *count, geom_error_report *report, geom_diag *diag);
geom_status geom_curve_nurbs_polyline_estimate(const geom_nurbs_curve *c,
    const geom_curve_polyline_options *options, double *count, int *is_bound, geom_diag *diag);
geom_status geom_curve_nurbs_eval_many(const geom_nurbs_curve *c, size_t n, const double *u,
                                                unsigned flags, double *out, int32_t *status,
                                                size_t *n_failed);
geom_status geom_curve_bspline_basis_many(int degree, size_t n, const double *knots, size_t m,
                                                   const double *u, int nderiv, unsigned flags,
                                                   size_t *spans, double *ders, int32_t *status,
                                                   size_t *n_failed);
geom_status geom_curve_nurbs_refine(const geom_nurbs_curve *c, const double *x, size_t nx,
                                    double *knots, double *points, double *weights,
                                    geom_nurbs_curve *out, geom_diag *diag);
geom_status geom_curve_nurbs_remove_knot(const geom_nurbs_curve *c, double u, size_t times,
                                         double tol, double *knots, double *points, double *weights,
                                         geom_nurbs_curve *out, size_t *removed, geom_diag *diag);
geom_status geom_curve_bspline_find_span(int degree, size_t n, const double *knots, double u,
                                         unsigned flags, size_t *span);
geom_status geom_curve_hermite_spline_to_bezier(size_t dim, size_t n, const double *points,
    const double *tangents, const double *params, double *bezier);
geom_status geom_curve_piecewise_bezier_knots(int degree, size_t nseg, const double *params,
    double *knots);
typedef enum geom_curve_end {
    GEOM_CURVE_END_EXTRAPOLATE = 0,
    GEOM_CURVE_END_EXCLUDE = 1,
    GEOM_CURVE_END_CLOSED = 2
} geom_curve_end;
geom_status geom_curve_catmull_rom_segments(size_t n, geom_curve_end ends, size_t *nseg);
geom_status geom_curve_catmull_rom_to_bezier(size_t dim, size_t n, const double *points,
    double alpha, geom_curve_end ends, double *bezier, double *params, geom_diag *diag);
typedef struct geom_kb_params {
    double tension;
    double continuity;
    double bias;
} geom_kb_params;
geom_status geom_curve_kochanek_bartels_to_bezier(size_t dim, size_t n, const double *points,
    const geom_kb_params *tcb, size_t ntcb, geom_curve_end ends, double *bezier,
    geom_diag *diag);
geom_status geom_curve_bezier_split(int degree, size_t dim, const double *ctrl, double t, double *left, double *right);
geom_status geom_curve_bezier_elevate(int degree, size_t dim, const double *ctrl, int times, double *out);
geom_status geom_curve_bezier_bbox(int degree, size_t dim, const double *ctrl, double *min, double *max);
geom_status geom_curve_bezier_bbox_tight(int degree, size_t dim, const double *ctrl, double *min, double *max);
geom_status geom_curve_hermite_to_bezier(size_t dim, const double *p0, const double *m0, const double *p1, const double *m1, double *bezier);
geom_status geom_curve_hermite_eval(size_t dim, const double *p0, const double *m0, const double *p1, const double *m1, double t, int nderiv, double *ders);
geom_status geom_curve_catmull_rom_eval(size_t dim, const double *p0, const double *p1, const double *p2, const double *p3, double alpha, double s, double *out);
geom_status geom_curve_nurbs_periodic(int degree, size_t m, size_t dim, const double *points, const double *weights, double *knots, double *points_out, double *weights_out, geom_nurbs_curve *out);
geom_status geom_curve_nurbs_clamp(const geom_nurbs_curve *c, double *knots, double *points, double *weights, geom_nurbs_curve *out, geom_diag *diag);
geom_status geom_curve_nurbs_segments(const geom_nurbs_curve *c, size_t *nseg);
geom_status geom_curve_nurbs_decompose(const geom_nurbs_curve *c, double *bezier_points, double *bezier_weights, double *breaks, geom_diag *diag);
geom_status geom_curve_nurbs_ellipse_arc(size_t dim, const double *center, const double *xaxis, const double *yaxis, double start, double end, double *knots, double *points, double *weights, geom_nurbs_curve *out, geom_diag *diag);
geom_status geom_curve_nurbs_conic(size_t dim, const double *p0, const double *t0, const double *p2, const double *t2, const double *point, double weight, double *knots, double *points, double *weights, geom_nurbs_curve *out, geom_diag *diag);
double geom_curve_segment_distance(size_t dim, const double *a, const double *b, const double *q);
""",
    "surface": """
typedef struct geom_nurbs_surface {
    int degree_u, degree_v;
    size_t nu, nv;
    const double *knots_u;
    const double *knots_v;
    const double *points;
    const double *weights;
} geom_nurbs_surface;
geom_status geom_surface_validate(const geom_nurbs_surface *s, geom_diag *diag);
geom_status geom_surface_domain(const geom_nurbs_surface *s, double domain[4]);
geom_status geom_surface_eval(const geom_nurbs_surface *s, double u, double v, unsigned flags,
    double out[3]);
geom_status geom_surface_derivs(const geom_nurbs_surface *s, double u, double v, int d, unsigned
    flags, double *ders);
geom_status geom_surface_normal(const geom_nurbs_surface *s, double u, double v, unsigned flags,
    double n[3], int *how);
geom_status geom_surface_bezier(int degree_u, int degree_v, const double *points, const double
    *weights, double *knots_u, double *knots_v, geom_nurbs_surface *out);
geom_status geom_surface_bilinear(const double p00[3], const double p10[3], const double p01[3],
    const double p11[3], double *knots_u, double *knots_v, double *points, geom_nurbs_surface
    *out);
typedef struct geom_surface_frame {
    double center[3];
    double zaxis[3];
    double xaxis[3];
} geom_surface_frame;
geom_status geom_surface_sphere(const geom_surface_frame *frame, double radius, double *knots_u,
    double *knots_v, double *points, double *weights, geom_nurbs_surface *out);
geom_status geom_surface_cylinder(const geom_surface_frame *frame, double radius, double height,
    double *knots_u, double *knots_v, double *points, double *weights, geom_nurbs_surface *out);
geom_status geom_surface_cone(const geom_surface_frame *frame, double r0, double r1, double
    height, double *knots_u, double *knots_v, double *points, double *weights,
    geom_nurbs_surface *out);
geom_status geom_surface_torus(const geom_surface_frame *frame, double major_radius, double
    minor_radius, double *knots_u, double *knots_v, double *points, double *weights,
    geom_nurbs_surface *out);
typedef struct geom_surface_set geom_surface_set;
void geom_surface_set_destroy(geom_surface_set *set);
size_t geom_surface_set_count(const geom_surface_set *set);
const geom_nurbs_surface *geom_surface_set_data(const geom_surface_set *set);
const char *geom_surface_set_name(const geom_surface_set *set, size_t i);
geom_status geom_surface_read_bpt(const char *path, const geom_allocator *alloc,
    geom_surface_set **out, geom_diag *diag);
geom_status geom_surface_read_bpt_memory(const void *data, size_t size, const char *source_name,
    const geom_allocator *alloc, geom_surface_set **out, geom_diag *diag);
typedef enum geom_surface_tess_mode {
    GEOM_SURFACE_TESS_ADAPTIVE = 0,
    GEOM_SURFACE_TESS_UNIFORM = 1
} geom_surface_tess_mode;
typedef struct geom_surface_tess_options {
    geom_surface_tess_mode mode;
    double tolerance;
    double angle_degrees;
    int grid_u, grid_v;
    int per_surface;
    unsigned attributes;
    int uv_normalized;
    int no_weld;
    int keep_orientation;
    int check_subdivisions;
    size_t max_triangles;
    const geom_allocator *alloc;
    double normal_weld_degrees;
    void (*progress)(void *user, double fraction);
    void *progress_user;
} geom_surface_tess_options;
typedef struct geom_surface_tess_stats {
    size_t cells;
    size_t triangles;
    size_t vertices;
    size_t welded_edges;
    size_t collapsed_edges;
    size_t flipped_surfaces;
    size_t boundary_edges;
    size_t refinements;
    size_t limit_normals;
    size_t welded_normals;
    uint32_t uniform_u, uniform_v;
} geom_surface_tess_stats;
geom_status geom_surface_tessellate(const geom_nurbs_surface *surfaces, size_t n, const
    geom_surface_tess_options *options, geom_mesh *out, geom_error_report *report,
    geom_surface_tess_stats *stats, geom_diag *diag);
geom_status geom_surface_eval_many(const geom_nurbs_surface *s, size_t n, const double *uv,
                                            unsigned flags, int normals, double *out,
                                            int32_t *status, size_t *n_failed);
geom_status geom_surface_extrude(const geom_nurbs_curve *c, const double d[3], double *knots_u, double *knots_v, double *points, double *weights, geom_nurbs_surface *out, geom_diag *diag);
geom_status geom_surface_ruled_bound(const geom_nurbs_curve *c0, const geom_nurbs_curve *c1, size_t *nu, size_t *nknots_u);
geom_status geom_surface_ruled(const geom_nurbs_curve *c0, const geom_nurbs_curve *c1, double *knots_u, double *knots_v, double *points, double *weights, geom_nurbs_surface *out, geom_diag *diag);
geom_status geom_surface_revolve_bound(double angle, size_t *nu, size_t *nknots_u);
geom_status geom_surface_revolve(const geom_nurbs_curve *c, const double origin[3], const double axis[3], const double *xaxis, double angle, double *knots_u, double *knots_v, double *points, double *weights, geom_nurbs_surface *out, geom_diag *diag);
geom_status geom_surface_tess_estimate(const geom_nurbs_surface *s, size_t n, const geom_surface_tess_options *opt, double *triangles);
""",
    "step": """
typedef enum geom_brep_curve_type {
    GEOM_BREP_CURVE_LINE = 0,
    GEOM_BREP_CURVE_CIRCLE = 1,
    GEOM_BREP_CURVE_ELLIPSE = 2,
    GEOM_BREP_CURVE_NURBS = 3
} geom_brep_curve_type;
typedef struct geom_brep_curve {
    geom_brep_curve_type type;
    uint64_t entity;
    int dim;
    double origin[3], x[3], y[3], z[3];
    double dir[3];
    double r1, r2;
    geom_nurbs_curve nurbs;
    size_t nknots;
} geom_brep_curve;
typedef enum geom_brep_surface_type {
    GEOM_BREP_SURFACE_PLANE = 0,
    GEOM_BREP_SURFACE_CYLINDER = 1,
    GEOM_BREP_SURFACE_CONE = 2,
    GEOM_BREP_SURFACE_SPHERE = 3,
    GEOM_BREP_SURFACE_TORUS = 4,
    GEOM_BREP_SURFACE_NURBS = 5,
    GEOM_BREP_SURFACE_REVOLUTION = 6,
    GEOM_BREP_SURFACE_EXTRUSION = 7
} geom_brep_surface_type;
typedef struct geom_brep_surface {
    geom_brep_surface_type type;
    uint64_t entity;
    double origin[3], x[3], y[3], z[3];
    double r1;
    double r2;
    double dir[3];
    uint32_t curve;
    geom_nurbs_surface nurbs;
    int u_periodic, v_periodic;
} geom_brep_surface;
typedef struct geom_brep_vertex {
    double p[3];
    uint64_t entity;
} geom_brep_vertex;
typedef struct geom_brep_edge {
    uint32_t v0, v1;
    uint32_t curve;
    int same_sense;
    double t0, t1;
    uint32_t pcurve[2];
    uint32_t pcurve_surface[2];
    uint64_t entity;
} geom_brep_edge;
typedef struct geom_brep_coedge {
    uint32_t edge;
    int reversed;
} geom_brep_coedge;
typedef struct geom_brep_loop {
    uint32_t first, n;
    int outer;
    int orientation;
    uint32_t vertex;
    uint64_t entity;
} geom_brep_loop;
typedef struct geom_brep_face {
    uint32_t surface;
    int same_sense;
    uint32_t first_loop, nloops;
    uint32_t shell;
    uint64_t entity;
} geom_brep_face;
typedef struct geom_brep_shell {
    uint32_t first_face, nfaces;
    int closed;
    uint32_t solid;
    uint64_t entity;
} geom_brep_shell;
typedef struct geom_brep_solid {
    uint32_t first_shell, nshells;
    uint64_t entity;
} geom_brep_solid;
typedef struct geom_brep_issue {
    uint64_t entity;
    char type[48];
    char reason[80];
} geom_brep_issue;
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
    size_t nissues;
    geom_brep_issue *issues;
    size_t nskipped_faces;
    double unit_metres;
    size_t ninstances;
    void *internal_;
} geom_brep;
typedef struct geom_step_read_options {
    double unit_metres;
    size_t max_bytes;
    int max_depth;
    int strict;
    const geom_allocator *alloc;
} geom_step_read_options;
geom_status geom_step_read_memory(const void *data, size_t size, const char *source_name,
                                           const geom_step_read_options *options, geom_brep **out,
                                           geom_diag *diag);
geom_status geom_step_read(const char *path, const geom_step_read_options *options,
                                    geom_brep **out, geom_diag *diag);
void geom_step_destroy(geom_brep *b);
geom_status geom_step_surface_eval(const geom_brep *b, uint32_t s, double u, double v,
                                            double p[3], double du[3], double dv[3]);
geom_status geom_step_curve_eval(const geom_brep *b, uint32_t c, double t, double *p);
typedef struct geom_brep_tess_options {
    double tolerance;
    double angle_degrees;
    unsigned attributes;
    size_t max_triangles;
    const geom_allocator *alloc;
} geom_brep_tess_options;
typedef struct geom_brep_face_report {
    double chordal_error;
    double edge_gap;
    size_t triangles;
    double seconds;
    int status;
} geom_brep_face_report;
typedef struct geom_brep_tess_stats {
    size_t faces, faces_failed, triangles, vertices;
    size_t edge_samples;
    double edge_gap;
    double edge_error;
    size_t open_edges;
    size_t nonmanifold_edges;
    double seconds;
} geom_brep_tess_stats;
geom_status geom_step_tessellate(const geom_brep *b, const geom_brep_tess_options *options,
                                          geom_mesh *out, geom_error_report *report,
                                          geom_brep_face_report *faces, geom_brep_tess_stats *stats,
                                          geom_diag *diag);
geom_status geom_step_tess_estimate(const geom_brep *b, const geom_brep_tess_options *options,
                                             double *triangles, double *per_face);
""",
    "subdiv": """
typedef enum geom_subdiv_scheme {
    GEOM_SUBDIV_CATMULL_CLARK = 0,
    GEOM_SUBDIV_LOOP = 1,
    GEOM_SUBDIV_BILINEAR = 2,
    GEOM_SUBDIV_BUTTERFLY = 3,
    GEOM_SUBDIV_SQRT3 = 4
} geom_subdiv_scheme;
typedef enum geom_subdiv_boundary {
    GEOM_SUBDIV_BOUNDARY_DEFAULT = 0,
    GEOM_SUBDIV_BOUNDARY_NONE = 1,
    GEOM_SUBDIV_BOUNDARY_EDGE_ONLY = 2,
    GEOM_SUBDIV_BOUNDARY_EDGE_AND_CORNER = 3
} geom_subdiv_boundary;
typedef enum geom_subdiv_fvar {
    GEOM_SUBDIV_FVAR_DEFAULT = 0,
    GEOM_SUBDIV_FVAR_NONE = 1,
    GEOM_SUBDIV_FVAR_CORNERS_ONLY = 2,
    GEOM_SUBDIV_FVAR_CORNERS_PLUS1 = 3,
    GEOM_SUBDIV_FVAR_CORNERS_PLUS2 = 4,
    GEOM_SUBDIV_FVAR_BOUNDARIES = 5,
    GEOM_SUBDIV_FVAR_ALL = 6
} geom_subdiv_fvar;
typedef enum geom_subdiv_crease {
    GEOM_SUBDIV_CREASE_DEFAULT = 0,
    GEOM_SUBDIV_CREASE_UNIFORM = 1,
    GEOM_SUBDIV_CREASE_CHAIKIN = 2
} geom_subdiv_crease;
typedef enum geom_subdiv_triangles {
    GEOM_SUBDIV_TRIANGLES_DEFAULT = 0,
    GEOM_SUBDIV_TRIANGLES_CATMARK = 1,
    GEOM_SUBDIV_TRIANGLES_SMOOTH = 2
} geom_subdiv_triangles;
typedef struct geom_subdiv_options {
    geom_subdiv_scheme scheme;
    geom_subdiv_boundary boundary;
    geom_subdiv_fvar fvar_boundary;
    geom_subdiv_crease crease_method;
    geom_subdiv_triangles triangles;
    int ignore_tags;
    size_t n_creases;
    const uint32_t *crease_verts;
    const double *crease_sharpness;
    size_t n_corners;
    const uint32_t *corner_verts;
    const double *corner_sharpness;
    size_t n_holes;
    const uint32_t *hole_faces;
    int partial_last_level;
    const geom_allocator *alloc;
} geom_subdiv_options;
geom_status geom_subdiv_scheme_from_name(const char *name, geom_subdiv_scheme *out);
const char *geom_subdiv_scheme_name(geom_subdiv_scheme s);
typedef struct geom_subdiv_report {
    int levels;
    size_t vertices, faces;
    size_t input_faces;
    size_t hole_faces;
    size_t fvar_channels;
    size_t dropped_channels;
    double max_limit_distance;
    double rms_limit_distance;
    double bbox_diagonal;
    geom_error_report error;
    double level_max_limit_distance;
    double level_rms_limit_distance;
} geom_subdiv_report;
geom_status geom_subdiv_mesh(const geom_mesh *m, const geom_subdiv_options *opt, int levels,
    unsigned flags, geom_mesh **out, geom_subdiv_report *report, geom_diag *diag);
typedef struct geom_subdiv_refiner geom_subdiv_refiner;
geom_status geom_subdiv_refiner_create(const geom_mesh *m, const geom_subdiv_options *opt, geom_subdiv_refiner **out, geom_diag *diag);
geom_status geom_subdiv_refiner_create_soup(size_t nverts, size_t nfaces, const uint32_t *face_sizes, const uint32_t *indices, const geom_subdiv_options *opt, geom_subdiv_refiner **out, geom_diag *diag);
void geom_subdiv_refiner_destroy(geom_subdiv_refiner *r);
geom_status geom_subdiv_refiner_add_fvar(geom_subdiv_refiner *r, size_t n_values, const uint32_t *face_values, uint32_t *channel);
size_t geom_subdiv_refiner_fvar_count(const geom_subdiv_refiner *r);
uint32_t geom_subdiv_refiner_fvar_mesh_channel(const geom_subdiv_refiner *r, uint32_t channel);
geom_status geom_subdiv_refiner_refine(geom_subdiv_refiner *r, int levels);
int geom_subdiv_refiner_max_level(const geom_subdiv_refiner *r);
geom_subdiv_scheme geom_subdiv_refiner_scheme(const geom_subdiv_refiner *r);
geom_subdiv_options geom_subdiv_refiner_options(const geom_subdiv_refiner *r);
typedef struct geom_subdiv_level_info {
    size_t vertices, edges, faces;
    size_t face_vertices;
    size_t max_valence;
    size_t sharp_edges;
    size_t hole_faces;
} geom_subdiv_level_info;
geom_status geom_subdiv_refiner_level_info(const geom_subdiv_refiner *r, int level, geom_subdiv_level_info *info);
geom_status geom_subdiv_refiner_faces(const geom_subdiv_refiner *r, int level, uint32_t *face_sizes, uint32_t *indices, uint8_t *is_hole);
const uint32_t *geom_subdiv_refiner_face_indices(const geom_subdiv_refiner *r, int level);
geom_status geom_subdiv_refiner_edges(const geom_subdiv_refiner *r, int level, uint32_t *verts, float *sharpness);
geom_status geom_subdiv_refiner_vertex_rules(const geom_subdiv_refiner *r, int level, float *sharpness, uint8_t *rule);
typedef enum geom_subdiv_origin {
    GEOM_SUBDIV_FROM_FACE = 0, GEOM_SUBDIV_FROM_EDGE = 1, GEOM_SUBDIV_FROM_VERTEX = 2} geom_subdiv_origin;
uint32_t geom_subdiv_refiner_child_vertex(const geom_subdiv_refiner *r, int level, geom_subdiv_origin kind, uint32_t index);
geom_status geom_subdiv_refiner_vertex_parent(const geom_subdiv_refiner *r, int level, uint32_t v, geom_subdiv_origin *kind, uint32_t *parent);
uint32_t geom_subdiv_refiner_face_parent(const geom_subdiv_refiner *r, int level, uint32_t f);
geom_status geom_subdiv_interpolate(const geom_subdiv_refiner *r, int level, size_t ncomp, const double *src, double *dst);
geom_status geom_subdiv_interpolate_varying(const geom_subdiv_refiner *r, int level, size_t ncomp, const double *src, double *dst);
geom_status geom_subdiv_interpolate_face(const geom_subdiv_refiner *r, int level, size_t ncomp, const double *src, double *dst);
size_t geom_subdiv_fvar_size(const geom_subdiv_refiner *r, uint32_t channel, int level);
geom_status geom_subdiv_fvar_face_values(const geom_subdiv_refiner *r, uint32_t channel, int level, uint32_t *face_values);
geom_status geom_subdiv_interpolate_fvar(const geom_subdiv_refiner *r, uint32_t channel, int level, size_t ncomp, const double *src, double *dst);
geom_status geom_subdiv_limit(const geom_subdiv_refiner *r, size_t ncomp, const double *src, double *pos, double *tan1, double *tan2);
geom_status geom_subdiv_limit_normals(const geom_subdiv_refiner *r, const double *src, double *normals, size_t *n_degenerate);
geom_status geom_subdiv_limit_fvar(const geom_subdiv_refiner *r, uint32_t channel, size_t ncomp, const double *src, double *dst);
geom_status geom_subdiv_build_mesh(const geom_subdiv_refiner *r, int level, const double *positions, const double *normals, const geom_mesh *like, geom_mesh **out, size_t *hole_faces, geom_diag *diag);
int geom_subdiv_level_is_plain(const geom_subdiv_refiner *r, int level, const double *positions, int with_normals, const geom_mesh *like);
""",
    "iso": """
typedef struct geom_implicit_field geom_iso_field;
typedef enum geom_implicit_scalar geom_iso_scalar;
typedef struct geom_implicit_grid geom_iso_grid;
geom_status geom_iso_grid_check(const geom_implicit_grid *g);
typedef struct geom_iso_options {
    double iso;
    int refine;
    int max_iterations;
    int normals;
    int caps;
    int error;
    int threads;
    size_t slab_layers;
    const geom_allocator *alloc;
    int inside;
    void (*progress)(void *user, double fraction);
    void *progress_user;
    int dense;
    size_t block_size;
    size_t error_samples;
} geom_iso_options;
typedef struct geom_iso_report {
    geom_error_report vertex_error;
    geom_error_report sample_error;
    size_t unmeasured;
    double seconds;
    double error_seconds;
    size_t cells;
    size_t active_cells;
    size_t ambiguous_faces;
    size_t tunnels;
    size_t iso_nodes;
    size_t nan_nodes;
    size_t refined;
    size_t slabs;
    int threads;
    double signed_volume;
    geom_error_report error;
    size_t cells_evaluated;
    size_t blocks, blocks_skipped;
    size_t error_stride;
    size_t nan_first[3];
    double nan_point[3];
} geom_iso_report;
typedef struct geom_iso_surface {
    size_t n_vertices;
    double *xyz;
    double *normals;
    size_t n_triangles;
    uint32_t *tris;
    size_t n_cap_triangles;
    geom_iso_report report;
    geom_allocator alloc;
} geom_iso_surface;
geom_status geom_iso_extract(const geom_implicit_field *field, const double bounds[6], const
    size_t res[3], const geom_iso_options *opt, geom_iso_surface *out, geom_diag *diag);
geom_status geom_iso_extract_grid(const geom_implicit_grid *grid, const geom_iso_options *opt,
    geom_iso_surface *out, geom_diag *diag);
typedef struct geom_iso_chunk {
    size_t first_vertex;
    size_t n_vertices;
    const double *xyz;
    const double *normals;
    size_t n_triangles;
    const uint32_t *tris;
    int caps;
} geom_iso_chunk;
typedef geom_status (*geom_iso_chunk_fn)(void *user, const geom_iso_chunk *chunk);
geom_status geom_iso_extract_stream(const geom_implicit_field *field, const double bounds[6],
    const size_t res[3], const geom_iso_options *opt, geom_iso_chunk_fn fn, void *user,
    geom_iso_surface *out, geom_diag *diag);
void geom_iso_surface_free(geom_iso_surface *s);
geom_status geom_iso_surface_to_mesh(const geom_iso_surface *s, geom_mesh *m, geom_diag *diag);
geom_status geom_iso_field_from_expr(const geom_implicit_expr *e, geom_implicit_field *out);
geom_status geom_iso_estimate_triangles(const geom_implicit_field *f, const double bounds[6], const size_t res[3], const geom_iso_options *opt, double *triangles);
geom_status geom_iso_grid_estimate_triangles(const geom_implicit_grid *g, const geom_iso_options *opt, double *triangles);
geom_status geom_iso_measure_error(const geom_implicit_field *field, double iso, size_t n_vertices, const double *xyz, size_t n_triangles, const uint32_t *tris, geom_error_report *vertex_error, geom_error_report *sample_error, size_t *unmeasured);
""",
    "implicit": """
typedef struct geom_implicit_expr geom_implicit_expr;
typedef struct geom_implicit_expr_options {
    const geom_allocator *alloc;
    size_t max_length;
    size_t max_depth;
} geom_implicit_expr_options;
geom_status geom_implicit_expr_compile(const char *text, size_t len, const
    geom_implicit_expr_options *opt, geom_implicit_expr **out, geom_diag *diag);
void geom_implicit_expr_destroy(geom_implicit_expr *e);
void geom_implicit_expr_set_time(geom_implicit_expr *e, double t);
size_t geom_implicit_expr_size(const geom_implicit_expr *e);
unsigned geom_implicit_expr_variables(const geom_implicit_expr *e);
double geom_implicit_expr_eval(const geom_implicit_expr *e, const double p[3]);
void geom_implicit_expr_eval_many(const geom_implicit_expr *e, size_t n, const double *p, double
    *out);
double geom_implicit_expr_eval_grad(const geom_implicit_expr *e, const double p[3], double
    grad[3]);
void geom_implicit_expr_eval_grad_many(const geom_implicit_expr *e, size_t n, const double *p,
    double *values, double *grads);
geom_status geom_implicit_expr_eval_interval(const geom_implicit_expr *e, const double lo[3],
    const double hi[3], double out[2]);
typedef double (*geom_implicit_root_fn)(void *user, double x);
double geom_implicit_bracket_root(geom_implicit_root_fn fn, void *user, double a, double b, double
    fa, double fb, double x, int max_iterations, size_t *evaluations);
geom_status geom_implicit_expr_eval_bounds(const geom_implicit_expr *e, const double lo[3],
    const double hi[3], double out[2], int *defined);
geom_status geom_implicit_expr_eval_bounds_many(const geom_implicit_expr *e, size_t n, const
    double *lo, const double *hi, double *out, int *defined);
typedef double (*geom_implicit_value_fn)(void *user, const double p[3]);
typedef double (*geom_implicit_grad_fn)(void *user, const double p[3], double grad[3]);
typedef void (*geom_implicit_values_fn)(void *user, size_t n, const double *p, double *out);
typedef void (*geom_implicit_gradients_fn)(void *user, size_t n, const double *p, double *values,
                                           double *grads);
typedef int (*geom_implicit_bounds_fn)(void *user, const double lo[3], const double hi[3],
                                       double out[2]);
typedef struct geom_implicit_field {
    geom_implicit_value_fn value;
    geom_implicit_grad_fn gradient;
    void *user;
    int exact;
    geom_implicit_values_fn values;
    geom_implicit_gradients_fn gradients;
    geom_implicit_bounds_fn bounds;
} geom_implicit_field;
typedef enum geom_implicit_refine {
    GEOM_IMPLICIT_REFINE_AUTO = 0,
    GEOM_IMPLICIT_REFINE_ALWAYS = 1,
    GEOM_IMPLICIT_REFINE_NEVER = 2
} geom_implicit_refine;
typedef enum geom_implicit_scalar {
    GEOM_IMPLICIT_SCALAR_F32 = 1,
    GEOM_IMPLICIT_SCALAR_F64 = 2
} geom_implicit_scalar;
typedef struct geom_implicit_grid {
    size_t dims[3];
    geom_implicit_scalar type;
    const void *data;
    double spacing[3];
    double origin[3];
    int big_endian;
} geom_implicit_grid;
typedef struct geom_implicit_grid geom_implicit_volume_desc;
double geom_implicit_samples_value(const geom_implicit_grid *d, const void *data, const
    double p[3]);
void geom_implicit_samples_gradient(const geom_implicit_grid *d, const void *data, const
    double p[3], double grad[3]);
typedef struct geom_implicit_volume geom_implicit_volume;
geom_status geom_implicit_volume_create(const geom_implicit_grid *desc,
                                        const geom_allocator *alloc,
                                        geom_implicit_volume **out);
geom_status geom_implicit_volume_read_raw(const char *path, const geom_implicit_grid *desc,
                                          const geom_allocator *alloc,
                                          geom_implicit_volume **out, geom_diag *diag);
geom_status geom_implicit_volume_read_nrrd(const char *path, const geom_allocator *alloc,
                                           geom_implicit_volume **out, geom_diag *diag);
geom_status geom_implicit_volume_read_nrrd_memory(const void *data, size_t size,
                                                  const char *source_name,
                                                  const geom_allocator *alloc,
                                                  geom_implicit_volume **out, geom_diag *diag);
void geom_implicit_volume_destroy(geom_implicit_volume *v);
void geom_implicit_volume_get_desc(const geom_implicit_volume *v, geom_implicit_grid *out);
void *geom_implicit_volume_data(geom_implicit_volume *v);
const void *geom_implicit_volume_cdata(const geom_implicit_volume *v);
double geom_implicit_volume_at(const geom_implicit_volume *v, size_t i, size_t j, size_t k);
geom_aabb geom_implicit_volume_bounds(const geom_implicit_volume *v);
double geom_implicit_volume_eval(const geom_implicit_volume *v, const double p[3]);
double geom_implicit_volume_eval_grad(const geom_implicit_volume *v, const double p[3],
                                      double grad[3]);
double geom_implicit_volume_value_cb(void *user, const double p[3]);
double geom_implicit_volume_grad_cb(void *user, const double p[3], double grad[3]);
geom_status geom_implicit_volume_detect_inside(const geom_implicit_volume *v, double iso,
                                                        int *above, size_t *below, size_t *total);
typedef enum geom_implicit_sample {
    GEOM_IMPLICIT_SAMPLE_U8 = 1,
    GEOM_IMPLICIT_SAMPLE_I8 = 2,
    GEOM_IMPLICIT_SAMPLE_U16 = 3,
    GEOM_IMPLICIT_SAMPLE_I16 = 4,
    GEOM_IMPLICIT_SAMPLE_U32 = 5,
    GEOM_IMPLICIT_SAMPLE_I32 = 6,
    GEOM_IMPLICIT_SAMPLE_F32 = 7,
    GEOM_IMPLICIT_SAMPLE_F64 = 8
} geom_implicit_sample;
typedef enum geom_implicit_volume_format {
    GEOM_IMPLICIT_VOLUME_AUTO = 0,
    GEOM_IMPLICIT_VOLUME_RAW = 1,
    GEOM_IMPLICIT_VOLUME_NRRD = 2,
    GEOM_IMPLICIT_VOLUME_METAIMAGE = 3,
    GEOM_IMPLICIT_VOLUME_INRIMAGE = 4,
    GEOM_IMPLICIT_VOLUME_NIFTI = 5
} geom_implicit_volume_format;
typedef geom_status (*geom_implicit_inflate_fn)(void *user, const void *in, size_t in_size,
                                                void *out, size_t out_cap, size_t *out_size);
typedef struct geom_implicit_volume_read_options {
    geom_implicit_volume_format format;
    size_t dims[3];
    geom_implicit_sample sample;
    double spacing[3];
    double origin[3];
    int big_endian;
    uint64_t skip;
    geom_implicit_inflate_fn inflate;
    void *inflate_user;
    geom_implicit_inflate_fn bunzip2;
    void *bunzip2_user;
} geom_implicit_volume_read_options;
typedef struct geom_implicit_volume_file_info {
    geom_implicit_volume_format format;
    geom_implicit_sample sample;
    int compressed;
    int flipped[3];
    int scaled;
    int spacing_defaulted[3];
    char spacing_note[GEOM_DIAG_MESSAGE_MAX];
} geom_implicit_volume_file_info;
geom_status geom_implicit_volume_read(const char *path,
                                               const geom_implicit_volume_read_options *options,
                                               const geom_allocator *alloc,
                                               geom_implicit_volume **out,
                                               geom_implicit_volume_file_info *info,
                                               geom_diag *diag);
geom_status geom_implicit_volume_read_memory(const void *data, size_t size,
                                                      const char *source_name,
                                                      const geom_implicit_volume_read_options *options,
                                                      const geom_allocator *alloc,
                                                      geom_implicit_volume **out,
                                                      geom_implicit_volume_file_info *info,
                                                      geom_diag *diag);
const char *geom_implicit_sample_name(geom_implicit_sample s);
geom_status geom_implicit_sample_parse(const char *name, geom_implicit_sample *out);
size_t geom_implicit_sample_size(geom_implicit_sample s);
const char *geom_implicit_volume_format_name(geom_implicit_volume_format f);
void geom_implicit_volume_eval_many(const geom_implicit_volume *v, size_t n,
                                             const double *p, double *out, double *grad);
typedef struct geom_implicit_contour_options {
    double iso;
    double z;
    int refine;
    int max_iterations;
    const geom_allocator *alloc;
} geom_implicit_contour_options;
typedef struct geom_implicit_contour_report {
    geom_error_report error;
    size_t unmeasured;
    double seconds;
    size_t cells;
    size_t saddles;
    size_t skipped_cells;
    size_t refined;
    size_t nan_nodes;
    size_t nan_first[2];
    double nan_point[2];
} geom_implicit_contour_report;
typedef struct geom_implicit_isolines {
    size_t n_vertices;
    double *xy;
    size_t n_polylines;
    size_t *start;
    uint32_t *indices;
    unsigned char *closed;
    geom_implicit_contour_report report;
    geom_allocator alloc;
} geom_implicit_isolines;
geom_status geom_implicit_contour(const geom_implicit_field *field, const double bounds[4], size_t nx, size_t ny, const geom_implicit_contour_options *opt, geom_implicit_isolines *out, geom_diag *diag);
geom_status geom_implicit_contour_estimate(const geom_implicit_field *field, const double bounds[4], size_t nx, size_t ny, const geom_implicit_contour_options *opt, double *vertices);
geom_status geom_implicit_contour_estimate_cells(const geom_implicit_field *field, const double bounds[4], size_t nx, size_t ny, const geom_implicit_contour_options *opt, double *cells);
void geom_implicit_isolines_free(geom_implicit_isolines *c);
geom_status geom_implicit_isolines_to_mesh(const geom_implicit_isolines *c, double z, geom_mesh *m);
""",
    "ray": """
typedef struct geom_ray_hit {
    double t;
    geom_vec3 point;
    geom_vec3 ng;
    geom_vec3 ns;
    double u, v;
    uint32_t prim;
    uint32_t object;
    double t_error;
    geom_vec3 p_error;
    int enter;
} geom_ray_hit;
geom_vec3 geom_ray_offset_origin(const geom_ray_hit *hit, geom_vec3 dir);
geom_status geom_ray_check(const geom_ray *r);
int geom_ray_triangle(const geom_ray *r, const double v0[3], const double v1[3],
    const double v2[3], geom_ray_hit *hit);
size_t geom_ray_poly_roots(const double *c, int deg, double lo, double hi, double *roots);
typedef struct geom_ray_scene geom_ray_scene;
geom_ray_scene *geom_ray_scene_create(const geom_allocator *alloc);
void geom_ray_scene_destroy(geom_ray_scene *s);
geom_status geom_ray_scene_add_plane(geom_ray_scene *s, const double point[3],
    const double n[3], uint32_t *id);
geom_status geom_ray_scene_add_box(geom_ray_scene *s, const double min[3],
    const double max[3], uint32_t *id);
geom_status geom_ray_scene_add_sphere(geom_ray_scene *s, const double center[3],
    double radius, uint32_t *id);
geom_status geom_ray_scene_add_quadric(geom_ray_scene *s, const double q[10],
    const double clip[6], int capped, uint32_t *id);
geom_status geom_ray_scene_add_torus(geom_ray_scene *s, double major, double minor,
    uint32_t *id);
geom_status geom_ray_scene_add_triangles(geom_ray_scene *s, const double *positions,
    size_t nv, const uint32_t *tris, size_t nt, const double *normals, uint32_t *id);
geom_status geom_ray_scene_set_transform(geom_ray_scene *s, uint32_t id, const double m[16]);
typedef struct geom_ray_build_options {
    int bvh_method;
    int bvh_threads;
} geom_ray_build_options;
typedef struct geom_ray_build_info {
    size_t meshes;
    size_t triangles;
    size_t bvh_nodes;
    size_t bvh_bytes;
    size_t bezier_patches;
    size_t analytic;
} geom_ray_build_info;
geom_status geom_ray_scene_build(geom_ray_scene *s, const geom_ray_build_options *opt,
    geom_ray_build_info *info, geom_diag *diag);
geom_status geom_ray_scene_closest(const geom_ray_scene *s, const geom_ray *r,
    geom_ray_hit *hit, int *found);
geom_status geom_ray_scene_closest_many(const geom_ray_scene *s, const geom_ray *rays, size_t n,
    geom_ray_hit *hits, int *found);
geom_status geom_ray_scene_any(const geom_ray_scene *s, const geom_ray *r, int *found);
geom_status geom_ray_scene_all(const geom_ray_scene *s, const geom_ray *r,
    geom_ray_hit *hits, size_t cap, size_t *n);
geom_status geom_ray_scene_any_many(const geom_ray_scene *s, const geom_ray *rays, size_t n,
    int *found);
geom_status geom_ray_scene_all_many(const geom_ray_scene *s, const geom_ray *rays, size_t n,
    size_t *offsets, geom_ray_hit *hits, size_t cap, size_t *count);
typedef enum geom_ray_kind {
    GEOM_RAY_PLANE = 1, GEOM_RAY_DISK, GEOM_RAY_BOX, GEOM_RAY_OBOX, GEOM_RAY_SPHERE, GEOM_RAY_QUADRIC, GEOM_RAY_TORUS, GEOM_RAY_TRIANGLE, GEOM_RAY_POLYGON, GEOM_RAY_MESH, GEOM_RAY_SURFACE, GEOM_RAY_SUBDIV, GEOM_RAY_IMPLICIT, GEOM_RAY_VOLUME, GEOM_RAY_CSG, GEOM_RAY_INSTANCE, GEOM_RAY_GROUP} geom_ray_kind;
typedef enum geom_ray_csg_op {
    GEOM_RAY_CSG_UNION = 1, GEOM_RAY_CSG_INTERSECTION, GEOM_RAY_CSG_DIFFERENCE} geom_ray_csg_op;
const char *geom_ray_kind_name(geom_ray_kind k);
geom_status geom_ray_scene_add_disk(geom_ray_scene *s, const double center[3], const double n[3], double radius, uint32_t *id);
geom_status geom_ray_scene_add_obox(geom_ray_scene *s, const double center[3], const double axes[9], const double half[3], uint32_t *id);
geom_status geom_ray_scene_add_triangle(geom_ray_scene *s, const double v[9], uint32_t *id);
geom_status geom_ray_scene_add_polygon(geom_ray_scene *s, const double *v, size_t n, uint32_t *id);
geom_status geom_ray_scene_add_mesh(geom_ray_scene *s, const geom_mesh *m, uint32_t *id);
geom_status geom_ray_scene_add_surface(geom_ray_scene *s, const geom_nurbs_surface *surf, uint32_t *id, geom_diag *diag);
geom_status geom_ray_scene_add_subdiv(geom_ray_scene *s, const geom_mesh *m, int scheme, int levels, uint32_t *id, geom_diag *diag);
geom_status geom_ray_scene_add_implicit(geom_ray_scene *s, const geom_implicit_expr *e, const double bounds[6], double lipschitz, uint32_t *id);
geom_status geom_ray_scene_add_volume(geom_ray_scene *s, const geom_implicit_volume *v, double iso, uint32_t *id);
typedef struct geom_ray_volume_options {
    int inside;
} geom_ray_volume_options;
geom_status geom_ray_scene_add_volume_opt(geom_ray_scene *s, const geom_implicit_volume *v, double iso, const geom_ray_volume_options *opt, uint32_t *id);
geom_status geom_ray_scene_add_csg(geom_ray_scene *s, geom_ray_csg_op op, uint32_t a, uint32_t b, uint32_t *id);
geom_status geom_ray_scene_add_group(geom_ray_scene *s, const uint32_t *ids, size_t n, uint32_t *id);
geom_status geom_ray_scene_add_instance(geom_ray_scene *s, uint32_t of, const double m[16], uint32_t *id);
geom_status geom_ray_scene_set_name(geom_ray_scene *s, uint32_t id, const char *name);
uint32_t geom_ray_scene_find(const geom_ray_scene *s, const char *name);
geom_status geom_ray_scene_set_objects(geom_ray_scene *s, const uint32_t *ids, size_t n);
size_t geom_ray_scene_node_count(const geom_ray_scene *s);
size_t geom_ray_scene_object_count(const geom_ray_scene *s);
uint32_t geom_ray_scene_object_node(const geom_ray_scene *s, size_t i);
geom_ray_kind geom_ray_scene_node_kind(const geom_ray_scene *s, uint32_t id);
geom_status geom_ray_scene_object_error(const geom_ray_scene *s, uint32_t id, geom_error_report *out);
typedef enum geom_ray_quadric_shape {
    GEOM_RAY_QUADRIC_ELLIPSOID = 1, GEOM_RAY_QUADRIC_CYLINDER, GEOM_RAY_QUADRIC_CONE, GEOM_RAY_QUADRIC_PARABOLOID, GEOM_RAY_QUADRIC_HYPERBOLOID1, GEOM_RAY_QUADRIC_HYPERBOLOID2} geom_ray_quadric_shape;
geom_status geom_ray_quadric_make(geom_ray_quadric_shape shape, const double *p, double q[10]);
""",
    "scene": """
typedef enum geom_projection {
    GEOM_PROJECTION_PERSPECTIVE = 0,
    GEOM_PROJECTION_ORTHOGRAPHIC = 1
} geom_projection;
typedef enum geom_sampling {
    GEOM_SAMPLING_REGULAR = 0,  /**< k x k grid, k = ceil(sqrt(samples)) */
    GEOM_SAMPLING_JITTERED = 1, /**< k x k strata, one random point in each */
    GEOM_SAMPLING_ADAPTIVE = 2  /**< refine pixels whose samples disagree */
} geom_sampling;
typedef struct geom_camera {
    geom_vec3 eye, center, up;   /**< as gluLookAt; up (0,0,0) means (0,1,0) */
    geom_projection projection;
    double fovy_degrees;         /**< perspective vertical field of view; 0 = 45 */
    double ortho_height;         /**< orthographic view height in world units; 0 = 2 */
    uint32_t width, height;      /**< pixels; 0 = 320 x 240 */
    uint32_t samples;            /**< per pixel for REGULAR/JITTERED; 0 = 1 */
    geom_sampling sampling;
    uint32_t max_samples;        /**< ADAPTIVE: per pixel at most; 0 = 64 */
    double tolerance;            /**< ADAPTIVE: refine while the samples' standard
                                      error exceeds this; 0 = 1/512 */
    uint64_t seed;               /**< JITTERED/ADAPTIVE random stream; 0 = fixed default */
} geom_camera;
geom_camera geom_scene_camera_resolved(const geom_camera *cam);
geom_status geom_scene_camera_ray(const geom_camera *cam, double x, double y, geom_ray *out);
geom_status geom_scene_camera_matrices(const geom_camera *cam, double near_z, double far_z,
                                          geom_mat4 *view, geom_mat4 *proj);
geom_status geom_scene_camera_project(const geom_camera *cam, geom_vec3 p, double out[3]);
double geom_scene_camera_pixel_size(const geom_camera *cam, double depth);
double geom_scene_pixel_tolerance(const geom_camera *cam, geom_aabb box,
                                           double pixel_error, int *visible);
typedef enum geom_aov {
    GEOM_AOV_COLOR = 0,
    GEOM_AOV_DEPTH = 1,
    GEOM_AOV_NORMAL = 2,
    GEOM_AOV_OBJECT = 3
} geom_aov;
typedef struct geom_trace_options {
    geom_aov aov;
    geom_vec3 background;
    uint32_t max_depth;
    double min_weight;
    int no_shadows;
    const geom_allocator *alloc;
    void (*progress)(void *user, double fraction);
    void *progress_user;
} geom_trace_options;
typedef enum geom_render_method {
    GEOM_RENDER_RAY = 0,
    GEOM_RENDER_RASTER = 1
} geom_render_method;
typedef struct geom_render_options {
    geom_render_method method;
    geom_aov aov;
    geom_vec3 background;
    double pixel_error;
    double tolerance;
    uint32_t max_depth;
    double min_weight;
    int no_shadows;
    uint32_t shadow_map_size;
    void (*progress)(void *user, double fraction);
    void *progress_user;
} geom_render_options;
typedef struct geom_texture geom_texture;
typedef enum geom_shading {
    GEOM_SHADING_PHONG = 0, GEOM_SHADING_GOURAUD = 1, GEOM_SHADING_FLAT = 2} geom_shading;
typedef enum geom_specular {
    GEOM_SPECULAR_BLINN = 0, GEOM_SPECULAR_PHONG = 1} geom_specular;
typedef enum geom_style {
    GEOM_STYLE_STANDARD = 0, GEOM_STYLE_COOL_TO_WARM = 1} geom_style;
typedef struct geom_material {
    geom_vec3 ka, kd, ks;
    double ns;
    geom_specular specular;
    double reflect;
    double transmit;
    double ior;
    const geom_texture *texture;
    const geom_texture *bump;
    double bump_scale;
    const geom_texture *normal_map;
    const geom_texture *displace;
    double displace_scale;
    geom_shading shading;
    geom_style style;
    double gooch_b, gooch_y, gooch_alpha, gooch_beta;
    double line_width;
    double crease_degrees;
} geom_material;
geom_material geom_scene_material_default(void);
unsigned geom_scene_material_needs(const geom_material *m);
typedef enum geom_shape_kind {
    GEOM_SHAPE_SPHERE = 1, GEOM_SHAPE_BOX, GEOM_SHAPE_PLANE, GEOM_SHAPE_DISK, GEOM_SHAPE_TORUS, GEOM_SHAPE_QUADRIC, GEOM_SHAPE_POLYGON, GEOM_SHAPE_MESH, GEOM_SHAPE_SURFACE, GEOM_SHAPE_SUBDIV, GEOM_SHAPE_IMPLICIT, GEOM_SHAPE_VOLUME, GEOM_SHAPE_CSG, GEOM_SHAPE_GROUP} geom_shape_kind;
typedef struct geom_shape {
    geom_shape_kind kind;
    const char *name;
    double p[3], n[3], radius;
    double min[3], max[3];
    double major, minor;
    double q[10];
    const double *clip;
    int capped;
    const double *vertices;
    size_t n_vertices;
    const geom_mesh *mesh;
    int scheme;
    const geom_nurbs_surface *surfaces;
    size_t n_surfaces;
    const geom_implicit_expr *expr;
    double bounds[6];
    const geom_implicit_volume *volume;
    double iso;
    int csg_op;
    const struct geom_shape *a, *b;
    const struct geom_shape *const *members;
    size_t n_members;
    const geom_mat4 *transform;
    int inside;
} geom_shape;
typedef struct geom_scene_shapes geom_scene_shapes;
geom_status geom_scene_shapes_from_ray(const geom_ray_scene *rs, geom_scene_shapes **out, geom_diag *diag);
size_t geom_scene_shapes_count(const geom_scene_shapes *s);
const geom_shape *geom_scene_shapes_get(const geom_scene_shapes *s, size_t i);
const char *geom_scene_shapes_kind_name(const geom_scene_shapes *s, size_t i);
void geom_scene_shapes_destroy(geom_scene_shapes *s);
typedef struct geom_tess_request {
    double tol;
    unsigned attributes;
    geom_aabb extent;
} geom_tess_request;
typedef struct geom_tess_info {
    geom_error_report error;
    size_t triangles;
    double seconds;
    const char *method;
} geom_tess_info;
geom_status geom_scene_tessellate(const geom_shape *s, const geom_tess_request *rq, geom_mesh *out, geom_tess_info *info, geom_diag *diag);
geom_status geom_scene_tessellate_estimate(const geom_shape *s, const geom_tess_request *rq, double *triangles);
typedef struct geom_scene_object {
    const geom_shape *shape;
    uint32_t material;
} geom_scene_object;
typedef struct geom_export_options {
    double tolerance;
    double pixel_error;
    geom_mat4 world;
    double max_triangles;
} geom_export_options;
typedef struct geom_export_object_report {
    double tolerance;
    geom_tess_info tess;
    unsigned attributes;
} geom_export_object_report;
geom_status geom_scene_export(const geom_camera *cam, const geom_material *materials, size_t n_materials, const geom_scene_object *objects, size_t n, const char *const *names, const geom_export_options *opt, geom_mesh *out, geom_export_object_report *reports, geom_diag *diag);
geom_status geom_scene_export_estimate(const geom_camera *cam, const geom_material *materials, size_t n_materials, const geom_scene_object *objects, size_t n, const geom_export_options *opt, double *per_object, double *triangles, geom_diag *diag);
geom_aabb geom_scene_shape_bounds(const geom_shape *s);
geom_status geom_scene_mesh_transform(geom_mesh *m, geom_mat4 M);
typedef struct geom_image {
    uint32_t width, height, channels;
    double *data;
} geom_image;
geom_status geom_scene_image_init(geom_image *img, uint32_t width, uint32_t height, uint32_t channels, const geom_allocator *alloc);
void geom_scene_image_free(geom_image *img, const geom_allocator *alloc);
typedef enum geom_light_kind {
    GEOM_LIGHT_POINT = 0, GEOM_LIGHT_DIRECTIONAL = 1, GEOM_LIGHT_AMBIENT = 2} geom_light_kind;
typedef struct geom_light {
    geom_light_kind kind;
    geom_vec3 position;
    geom_vec3 direction;
    geom_vec3 color;
} geom_light;
typedef struct geom_trace_report {
    size_t primary_rays;
    size_t shadow_rays;
    size_t reflection_rays;
    size_t refraction_rays;
    size_t total_internal_reflections;
    size_t cut_by_depth;
    size_t cut_by_weight;
    uint32_t max_samples_per_pixel;
    double mean_samples_per_pixel;
    geom_error_report image_error;
    double seconds;
} geom_trace_report;
geom_status geom_scene_trace(const geom_ray_scene *rs, const uint32_t *object_material, size_t n_objects, const geom_camera *cam, const geom_light *lights, size_t n_lights, const geom_material *materials, size_t n_materials, const geom_trace_options *opt, geom_image *out, geom_trace_report *report);
typedef struct geom_raster_report {
    size_t triangles_in;
    size_t triangles_clipped;
    size_t fragments;
    size_t shadow_maps;
    uint32_t samples_per_pixel;
    double seconds_clip, seconds_raster, seconds_shade, seconds_shadow;
} geom_raster_report;
typedef struct geom_render_object_report {
    int visible;
    int needed;
    int acceleration;
    size_t accel_triangles;
    int tessellated;
    double tolerance;
    geom_tess_info tess;
    int normals, uvs, tangents;
    int displaced;
} geom_render_object_report;
typedef struct geom_render_report {
    double seconds_build;
    double seconds_render;
    size_t objects_needed;
    int refraction;
    int reflection;
    geom_ray_build_info ray_build;
    geom_trace_report trace;
    geom_raster_report raster;
} geom_render_report;
geom_status geom_scene_render(const geom_camera *cam, const geom_light *lights, size_t n_lights, const geom_material *materials, size_t n_materials, const geom_scene_object *objects, size_t n_objects, const geom_render_options *opt, geom_image *out, geom_render_report *report, geom_render_object_report *object_reports, geom_diag *diag);
typedef enum geom_wrap {
    GEOM_WRAP_REPEAT = 0,
    GEOM_WRAP_CLAMP = 1
} geom_wrap;
geom_status geom_scene_texture_create(const geom_image *img, geom_wrap wrap,
    const geom_allocator *alloc, geom_texture **out);
void geom_scene_texture_destroy(geom_texture *t);
uint32_t geom_scene_texture_channels(const geom_texture *t);
void geom_scene_texture_size(const geom_texture *t, uint32_t *width, uint32_t *height);
uint32_t geom_scene_texture_levels(const geom_texture *t);
void geom_scene_texture_sample(const geom_texture *t, double u, double v, double footprint,
    double *out);
void geom_scene_texture_gradient(const geom_texture *t, double u, double v, double *dh_du,
    double *dh_dv);
geom_status geom_scene_texture_sample_many(const geom_texture *t, size_t n, const double *uv,
    const double *footprint, size_t footprint_stride, double *out, double *grad);
typedef struct geom_shade_point {
    geom_vec3 p;
    geom_vec3 n;
    geom_vec3 ng;
    geom_vec3 v;
    double uv[2];
    int has_uv;
    geom_vec3 tangent;
    double tangent_sign;
    int has_tangent;
    double footprint;
} geom_shade_point;
geom_vec3 geom_scene_shade_normal(const geom_material *m, const geom_shade_point *sp);
void geom_scene_shade(const geom_material *m, const geom_light *lights, size_t n_lights,
    const double *visibility, const geom_shade_point *sp, geom_vec3 n,
    geom_vec3 *out);
typedef struct geom_scene_draw {
    const geom_mesh *mesh;
    const geom_mat4 *transform;
    uint32_t material;
    uint32_t object_id;
} geom_scene_draw;
typedef struct geom_raster_options {
    geom_aov aov;
    geom_vec3 background;
    int shadows;
    uint32_t shadow_map_size;
    double near_z, far_z;
    const geom_allocator *alloc;
} geom_raster_options;
geom_status geom_scene_raster(const geom_camera *cam, const geom_light *lights,
    size_t n_lights, const geom_material *materials,
    size_t n_materials, const geom_scene_draw *draws,
    size_t n_draws, const geom_raster_options *opt,
    geom_image *out, geom_raster_report *report);
geom_status geom_scene_displace(geom_mesh *m, const geom_texture *height, double scale);
""",
    "spatial": """
typedef struct geom_bvh geom_bvh;
typedef enum geom_bvh_method {
    GEOM_BVH_SAH = 0,
    GEOM_BVH_LBVH = 1
} geom_bvh_method;
typedef struct geom_bvh_options {
    geom_bvh_method method;
    uint32_t max_leaf_size;
    uint32_t bins;
    int threads;
    const geom_allocator *alloc;
} geom_bvh_options;
typedef struct geom_bvh_node {
    geom_aabb box;
    uint32_t index;
    uint32_t count;
    uint32_t axis;
    uint32_t pad;
} geom_bvh_node;
geom_status geom_bvh_build_triangles(const double *positions, size_t nv,
    const uint32_t *tris, size_t nt,
    const geom_bvh_options *opt, geom_bvh **out,
    geom_diag *diag);
geom_status geom_bvh_build_boxes(const geom_aabb *boxes, size_t n,
    const geom_bvh_options *opt, geom_bvh **out,
    geom_diag *diag);
typedef void (*geom_bvh_bounds_fn)(void *user, size_t i, geom_aabb *box);
geom_status geom_bvh_build_callback(size_t n, geom_bvh_bounds_fn fn, void *user,
    const geom_bvh_options *opt, geom_bvh **out,
    geom_diag *diag);
geom_status geom_bvh_refit_triangles(geom_bvh *b, const double *positions, size_t nv,
    const uint32_t *tris, size_t nt);
void geom_bvh_destroy(geom_bvh *b);
const geom_bvh_node *geom_bvh_nodes(const geom_bvh *b, size_t *count);
const uint32_t *geom_bvh_prim_indices(const geom_bvh *b, size_t *count);
size_t geom_bvh_depth(const geom_bvh *b);
size_t geom_bvh_bytes(const geom_bvh *b);
typedef struct geom_neighbors {
    size_t query_count;
    size_t *offsets;
    uint32_t *index;
    double *distance;
    size_t capacity;
    const geom_allocator *alloc;
} geom_neighbors;
void geom_neighbors_free(geom_neighbors *nb);
geom_status geom_bvh_query_boxes(const geom_bvh *b, const geom_aabb *prim_boxes,
    const geom_aabb *queries, size_t m, geom_neighbors *out, int threads, geom_diag *diag);
typedef struct geom_kdtree geom_kdtree;
typedef struct geom_kdtree_options {
    uint32_t leaf_size;
    int threads;
    const geom_allocator *alloc;
} geom_kdtree_options;
geom_status geom_kdtree_build(const double *points, size_t n, int dim,
    const geom_kdtree_options *opt, geom_kdtree **out,
    geom_diag *diag);
void geom_kdtree_destroy(geom_kdtree *t);
size_t geom_kdtree_node_count(const geom_kdtree *t);
size_t geom_kdtree_depth(const geom_kdtree *t);
size_t geom_kdtree_bytes(const geom_kdtree *t);
geom_status geom_kdtree_knn(const geom_kdtree *t, const double *queries, size_t nq,
    size_t k, uint32_t *index, double *distance,
    int threads, geom_diag *diag);
geom_status geom_kdtree_radius(const geom_kdtree *t, const double *queries, size_t nq,
    double r, geom_neighbors *out, int threads,
    geom_diag *diag);
geom_status geom_kdtree_box(const geom_kdtree *t, const double *lo, const double *hi,
    geom_neighbors *out);
typedef struct geom_octree geom_octree;
typedef struct geom_octree_options {
    uint32_t bucket_size;
    uint32_t max_depth;
    int balance;
    int threads;
    const geom_allocator *alloc;
} geom_octree_options;
typedef struct geom_octree_node {
    geom_aabb cell;
    geom_aabb bounds;
    uint32_t first_child;
    uint32_t child_mask;
    uint32_t item_start;
    uint32_t item_total;
    uint32_t own_count;
    uint32_t level;
} geom_octree_node;
geom_status geom_octree_build_points(const double *points, size_t n, int dim,
    const geom_octree_options *opt, geom_octree **out,
    geom_diag *diag);
geom_status geom_octree_build_segments(const double *positions, size_t nv,
    const uint32_t *segs, size_t ns,
    const geom_octree_options *opt, geom_octree **out,
    geom_diag *diag);
geom_status geom_octree_build_triangles(const double *positions, size_t nv,
    const uint32_t *tris, size_t nt,
    const geom_octree_options *opt, geom_octree **out,
    geom_diag *diag);
void geom_octree_destroy(geom_octree *t);
const geom_octree_node *geom_octree_nodes(const geom_octree *t, size_t *count);
const uint32_t *geom_octree_items(const geom_octree *t, size_t *count);
int geom_octree_dim(const geom_octree *t);
size_t geom_octree_depth(const geom_octree *t);
size_t geom_octree_bytes(const geom_octree *t);
geom_status geom_octree_knn(const geom_octree *t, const double *queries, size_t nq,
    size_t k, uint32_t *index, double *distance, int threads,
    geom_diag *diag);
geom_status geom_octree_radius(const geom_octree *t, const double *queries, size_t nq,
    double r, geom_neighbors *out, int threads,
    geom_diag *diag);
geom_status geom_octree_box(const geom_octree *t, const double *lo, const double *hi,
    geom_neighbors *out);
geom_status geom_octree_frustum(const geom_octree *t, const double planes[24],
    geom_neighbors *out);
typedef struct geom_meshdist geom_meshdist;
typedef struct geom_meshdist_options {
    uint32_t max_leaf_size;
    double beta;
    double tolerance;
    int threads;
    const geom_allocator *alloc;
} geom_meshdist_options;
geom_status geom_meshdist_create(const double *positions, size_t nv, const uint32_t *tris,
    size_t nt, const geom_meshdist_options *opt,
    geom_meshdist **out, geom_diag *diag);
void geom_meshdist_destroy(geom_meshdist *m);
const geom_bvh *geom_meshdist_bvh(const geom_meshdist *m);
size_t geom_meshdist_bytes(const geom_meshdist *m);
geom_status geom_meshdist_closest(const geom_meshdist *m, const double *queries, size_t nq,
    double *point, uint32_t *tri, double *bary,
    double *distance, int threads, geom_diag *diag);
geom_status geom_meshdist_winding(const geom_meshdist *m, const double *queries, size_t nq,
    double *w, geom_error_report *report, int threads,
    geom_diag *diag);
geom_status geom_meshdist_signed_distance(const geom_meshdist *m, const double *queries,
    size_t nq, double *sd,
    geom_error_report *report, int threads,
    geom_diag *diag);
geom_status geom_octree_ray(const geom_octree *t, const geom_ray *ray, geom_neighbors *out);
""",
}

#: One function per module whose presence in the library tells that the
#: module was built (a library configured with GEOM_MODULES=core;bary has
#: no mesh functions).
MODULE_PROBES = {
    "core": "geom_status_str",
    "bary": "geom_bary_tri2",
    "mesh": "geom_mesh_create",
    "meshio": "geom_meshio_read",
    "spatial": "geom_kdtree_build",
    "curve": "geom_curve_nurbs_eval",
    "surface": "geom_surface_tessellate",
    "step": "geom_step_read_memory",
    "subdiv": "geom_subdiv_mesh",
    "iso": "geom_iso_extract",
    "implicit": "geom_implicit_expr_compile",
    "ray": "geom_ray_scene_create",
    "scene": "geom_scene_camera_ray",
}


def expand_macros(text):
    """The declarations with the header macros replaced by their values."""
    for name, value in MACROS.items():
        text = text.replace(name, str(value))
    return text


ffi = cffi.FFI()
for _module in MODULE_ORDER:
    ffi.cdef(expand_macros(CDEFS[_module]))

_LOCAL_NAMES = ("libgeom.so", "libgeom.so.0", "libgeom.dylib", "geom.dll")


def _load():
    explicit = os.environ.get("GEOM_LIBRARY")
    if explicit:
        try:
            return ffi.dlopen(explicit), explicit
        except OSError as exc:
            raise ImportError(
                "geom: GEOM_LIBRARY=%r could not be loaded: %s" % (explicit, exc)) from exc
    here = os.path.dirname(os.path.abspath(__file__))
    tried = []
    for name in _LOCAL_NAMES:
        path = os.path.join(here, name)
        if os.path.exists(path):
            return ffi.dlopen(path), path
        tried.append(path)
    try:
        from ._libpath import LIBRARY
    except ImportError:
        LIBRARY = None
    if LIBRARY and os.path.exists(LIBRARY):
        return ffi.dlopen(LIBRARY), LIBRARY
    for name in (ctypes.util.find_library("geom"), "libgeom.so.0"):
        if not name:
            continue
        try:
            return ffi.dlopen(name), name
        except OSError:
            tried.append(name)
    raise ImportError(
        "geom: libgeom shared library not found; set GEOM_LIBRARY to the path of "
        "libgeom.so (e.g. build/libgeom/libgeom.so). Tried: " + ", ".join(tried))


lib, library_path = _load()


def has_module(name):
    """True if the loaded library contains the C module `name`."""
    try:
        getattr(lib, MODULE_PROBES[name])
    except (AttributeError, KeyError):
        return False
    return True
