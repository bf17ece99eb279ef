/*
 * libgeom meshio: reading and writing mesh files.
 *
 *   format  read  write  notes
 *   OBJ     yes   yes    v [w] [r g b], vt, vn, f, l, g/o/s/usemtl/mtllib, t tags
 *   OFF     yes   yes    ASCII; [ST][C][N]OFF variants (texture, colours, normals)
 *   PLY     yes   yes    ascii, binary_little_endian, binary_big_endian
 *   STL     yes   yes    ASCII and binary (binary detected by its size)
 *   GLB     yes   yes    glTF 2.0 binary container, triangle primitives (read:
 *                          every mode-4 primitive of the first mesh, welded by
 *                          position; attributes as CORNER channels)
 *
 * Reading parses the file into a polygon soup with attribute arrays and
 * builds the mesh with geom_mesh_build() (see mesh.h): the build options and
 * report are those of geom_mesh_build, so repairs (split non-manifold
 * vertices, flipped or detached faces, skipped invalid faces) are reported,
 * not errors. What each format becomes:
 *  - positions: the VERTEX channel "position" (always);
 *  - OBJ vt / vn: CORNER channels "uv" (2 comps: u v; a third vt value is
 *    ignored) and "normal" (3) with the file's value pools and indices, so
 *    seams and split normals are kept exactly and written back with the same
 *    v/vt/vn structure; OBJ vertex colours: VERTEX "color" (3), the
 *    homogeneous w: VERTEX "weight" (1) (vertices without them get 1);
 *  - OFF / PLY per-vertex normals, texture coordinates and colours: VERTEX
 *    channels "normal" (3), "uv" (2), "color" (3 or 4, in [0,1]: integer
 *    colours are divided by 255, PLY ushort ones by 65535); per-face colours:
 *    FACE "color"; PLY face "texcoord" lists (MeshLab): CORNER "uv";
 *  - STL: positions only, welded by exact position;
 *  - OBJ g/o/usemtl/s: the mesh's face groups; mtllib: its mtllibs; l: its
 *    polylines; t: its tags (OpenSubdiv's `t name nint/nfloat/nstring ...`).
 *    OBJ indices (1-based, or negative: relative to the end) must refer to
 *    v/vt/vn lines that come earlier in the file. Comments start with '#'
 *    anywhere on a line; a line ending in '\' continues on the next one.
 *    Other statements (vp, p, curv, cstype, ...) are skipped and counted.
 *
 * Errors name the source, the 1-based line and column (text) or the byte
 * offset (binary) and what was expected, through geom_diag. A header count
 * larger than the file can hold or than the element limit is rejected
 * before any allocation proportional to it. Readers never read outside their
 * input and never allocate more than a constant times the input size.
 *
 * Writers write whole files atomically: into a temporary file in the
 * destination's directory, renamed over the destination only when
 * everything succeeded; on failure the temporary file is removed and an
 * existing destination is left untouched. The temporary file is named
 * ".NAME.XXXXXXXX.geomtmp" (NAME shortened so that the name fits NAME_MAX),
 * so one left by a killed process is recognisable. What is never replaced:
 * a destination that is not a regular file (/dev/null, /dev/full, a FIFO,
 * a symbolic link to one) is opened and written through, and a write error
 * there (ENOSPC) is an error; a symbolic link to a regular file stays a
 * link (its target is replaced); a replaced file keeps its mode (and its
 * owner where the system allows); a file we may not write (faccessat W_OK)
 * is refused as cp refuses it; a dangling symbolic link is refused. Doubles are written with the
 * shortest decimal that reads back to the same bits (or a chosen precision).
 *
 * Numbers: text numbers must match [+-]digits[.digits][(e|E)[+-]digits]
 * (also "5." and ".5"); hexadecimal, NaN, infinities and values that
 * overflow a double are parse errors. Conversion is correctly rounded
 * (strtod for the cases a fast exact path does not cover; strtod follows
 * LC_NUMERIC, and the reader retries with the locale's decimal point, so
 * files use '.' whatever the locale). Writers always write '.'.
 *
 * Thread safety: every function is reentrant; no global state.
 */
#ifndef GEOM_MESHIO_H
#define GEOM_MESHIO_H

#include "geom/core.h"
#include "geom/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------- formats */

typedef enum geom_meshio_format {
    GEOM_MESHIO_FORMAT_AUTO = 0, /**< from the file name's extension, else the content */
    GEOM_MESHIO_FORMAT_OBJ = 1,
    GEOM_MESHIO_FORMAT_OFF = 2,
    GEOM_MESHIO_FORMAT_PLY = 3,
    GEOM_MESHIO_FORMAT_STL = 4,
    GEOM_MESHIO_FORMAT_GLB = 5 /**< glTF 2.0 binary */
} geom_meshio_format;

/**
 * The format named by `name`: a format name ("obj", "OFF", "glb") or a
 * path whose extension (after the last '.' of the last path component,
 * case-insensitive) is one: "mesh.OBJ" gives OBJ. Recognised: obj, off,
 * ply, stl, glb. Anything else, "" and NULL give GEOM_MESHIO_FORMAT_AUTO
 * (not recognised); ".gltf" (JSON glTF, not written by this module) is not
 * recognised either.
 */
GEOM_API geom_meshio_format geom_meshio_format_from_name(const char *name);

/** Lower-case name of a format ("obj", ..., "glb"; "auto" for AUTO,
 *  "unknown" for other values). Never NULL. */
GEOM_API const char *geom_meshio_format_name(geom_meshio_format format);

/**
 * Guess the format of file content: PLY ("ply" magic line), GLB ("glTF"
 * magic), binary STL (size = 84 + 50 * triangle count in the header), OFF
 * (first token ends in "OFF"), ASCII STL (first token "solid"), else OBJ.
 * data may be NULL when size is 0 (gives OBJ).
 */
GEOM_API geom_meshio_format geom_meshio_format_sniff(const void *data, size_t size);

/* ------------------------------------------------------------------ reading */

/** Default for geom_meshio_read_options.max_elements: 2^28. */
#define GEOM_MESHIO_DEFAULT_MAX_ELEMENTS ((size_t)1 << 28)

/** What a reader met besides the mesh (all zero when nothing to say). */
typedef struct geom_meshio_read_stats {
    geom_meshio_format format;   /**< the format actually read */
    int binary;                  /**< 1 for binary PLY/STL input */
    size_t skipped_statements;   /**< OBJ: unknown or unsupported statements (vp, p, curv,
                                      ...) and ignored vt w values; STL: none */
    char first_skipped[32];      /**< OBJ: keyword of the first skipped statement */
    size_t skipped_elements;     /**< PLY: instances of elements other than vertex/face */
    size_t skipped_properties;   /**< PLY: properties declared but not used */
    size_t welded_corners;       /**< STL: triangle corners merged into an earlier vertex */
    size_t input_vertices;       /**< vertices in the soup given to geom_mesh_build */
    size_t input_faces;          /**< faces in the soup (including invalid ones) */
} geom_meshio_read_stats;

/** Reading options; a zero-initialised struct (or NULL) gives the defaults. */
typedef struct geom_meshio_read_options {
    /** Format of the input; AUTO: from the path's (source_name's) extension,
     *  else from the content (geom_meshio_format_sniff). */
    geom_meshio_format format;
    /** Passed to geom_mesh_build. skip_invalid_faces also governs faces with
     *  fewer than 3 vertices or a repeated vertex (e.g. STL triangles that
     *  welding made degenerate): 0 makes them a parse error naming their
     *  line / offset, nonzero skips them and counts them in the build
     *  report's invalid_faces. */
    geom_mesh_build_options build;
    /** Largest number of elements (vertices, faces, face corners, attribute
     *  values, PLY element instances, tag values) accepted; more is
     *  GEOM_ERR_LIMIT. 0 means GEOM_MESHIO_DEFAULT_MAX_ELEMENTS. */
    size_t max_elements;
    /** Allocator for the mesh and all temporary memory; NULL = libc. */
    const geom_allocator *alloc;
    /** Optional output: filled with what was skipped (may be NULL). */
    geom_meshio_read_stats *stats;
    /** GLB input: nonzero says the mesh is wanted Z-up (as it was before
     *  a write with geom_meshio_write_options.gltf_z_up): it is rotated
     *  from glTF's Y-up frame, (x, y, z) -> (x, -z, y), positions, normals
     *  and tangents alike, undoing that write exactly. Other formats and 0
     *  (the default): read as stored. */
    int gltf_z_up;
} geom_meshio_read_options;

/**
 * Read a mesh file. `path` is mapped (geom_file_map: regular files) or
 * read whole, then parsed as geom_meshio_read_file would (diagnostics name
 * `path` as the source). *out receives a new mesh (free with
 * geom_mesh_destroy) on GEOM_OK and NULL otherwise. opt, report and diag may
 * be NULL; report is geom_mesh_build's report (zeroed on a parse error).
 *
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL path or out,
 * unknown opt->format); GEOM_ERR_IO (cannot open or read: diag has the
 * system's reason); GEOM_ERR_PARSE (malformed content: diag has the line
 * and column, or the byte offset, and what was expected); GEOM_ERR_LIMIT
 * (more elements than opt->max_elements, or indices beyond 2^32-2);
 * GEOM_ERR_NOMEM; and the statuses of geom_mesh_build.
 */
GEOM_API geom_status geom_meshio_read(const char *path, const geom_meshio_read_options *opt,
                             geom_mesh **out, geom_mesh_build_report *report, geom_diag *diag);

/**
 * Read a mesh from `size` bytes at `data` (which need not be NUL-terminated
 * and is never read beyond size; may be NULL when size is 0). source_name
 * (NULL: "<memory>") names the input in diagnostics and, with format AUTO,
 * gives the extension; without a recognised extension the content is
 * sniffed. Otherwise as geom_meshio_read (no GEOM_ERR_IO).
 */
GEOM_API geom_status geom_meshio_read_memory(const void *data, size_t size, const char *source_name,
                                    const geom_meshio_read_options *opt, geom_mesh **out,
                                    geom_mesh_build_report *report, geom_diag *diag);

/**
 * As geom_meshio_read_memory over file->data (from geom_file_map or
 * geom_file_map_fd), except that once the text is parsed and before the mesh
 * is built, the pages of a mapped file are released (the mapping stays
 * valid and reads back the same bytes from the file if touched again), so
 * the file and the mesh are not both in memory. The caller still releases
 * the file with geom_file_unmap.
 */
GEOM_API geom_status geom_meshio_read_file(geom_file *file, const char *source_name,
                                           const geom_meshio_read_options *opt, geom_mesh **out,
                                           geom_mesh_build_report *report, geom_diag *diag);

/* ------------------------------------------------------------------ writing */

/** Attribute bits for geom_meshio_write_options.omit. */
#define GEOM_MESHIO_ATTR_NORMAL 1u
#define GEOM_MESHIO_ATTR_UV 2u
#define GEOM_MESHIO_ATTR_COLOR 4u
#define GEOM_MESHIO_ATTR_TANGENT 8u
/** OBJ: omit tags (t), groups (g/o/usemtl/s), mtllibs and polylines (l). */
#define GEOM_MESHIO_ATTR_META 16u
/** OBJ: omit the mtllib lines only (a material library that is not next to
 *  the output would be a dangling reference). */
#define GEOM_MESHIO_ATTR_MTLLIB 32u

typedef enum geom_meshio_encoding {
    GEOM_MESHIO_ENCODING_DEFAULT = 0,  /**< PLY: binary little endian; STL: binary */
    GEOM_MESHIO_ENCODING_ASCII = 1,    /**< PLY, STL */
    GEOM_MESHIO_ENCODING_BINARY_LE = 2, /**< PLY, STL */
    GEOM_MESHIO_ENCODING_BINARY_BE = 3 /**< PLY only */
} geom_meshio_encoding;

/**
 * Writing options; a zero-initialised struct (or NULL) gives the defaults.
 *
 * Which attributes are written: every one of "normal", "uv", "color" and
 * "tangent" that the mesh has (CORNER channel first, else VERTEX channel of
 * that name) and the format can hold, less those in `omit`:
 *  - OBJ: uv and normal (vt/vn, from CORNER or VERTEX channels, pools written
 *    in order so indices are kept), VERTEX "color" (3 comps) and "weight"
 *    (w), groups, mtllibs, polylines (l) and tags (t);
 *  - OFF: normal, color (as 4 floats r g b a, always with a '.', so they
 *    read back as [0,1] values), uv (STCNOFF order) and FACE "color";
 *    PLY: normal (nx ny nz), uv (u v), color (uchar red green blue [alpha],
 *    rounded to k/255) and FACE "color" (uchar); for both, CORNER channels with seams (a vertex whose
 *    corners hold different values) make the writer split vertices, one per
 *    distinct (vertex, attribute values) corner;
 *  - STL: positions and face normals only (faces are triangulated);
 *  - GLB: POSITION, NORMAL, TEXCOORD_0 (v flipped to glTF's top-left
 *    origin unless gltf_keep_v), TANGENT (w negated with the flip so the
 *    bitangent stays right), COLOR_0, one vertex per distinct corner;
 *    polygons are triangulated (geom_mesh_triangulate on a copy).
 * Deleted elements are not written; vertices are renumbered densely.
 */
typedef struct geom_meshio_write_options {
    /** AUTO: from the path's extension (geom_meshio_write), required
     *  otherwise (geom_meshio_write_memory: AUTO is GEOM_ERR_INVALID_ARG). */
    geom_meshio_format format;
    /** PLY and STL encoding (see geom_meshio_encoding). */
    geom_meshio_encoding encoding;
    /** OR of GEOM_MESHIO_ATTR_* bits: attributes NOT to write. */
    unsigned omit;
    /** Significant digits of text doubles: 0 = shortest decimal that reads
     *  back to the same double (exact); 1..17 = printf "%.*g" (17 is exact,
     *  fewer are lossy). Values above 17 are treated as 17. */
    int precision;
    /** PLY binary: nonzero writes x y z and attributes as float instead of
     *  double (lossy, smaller). */
    int ply_float;
    /** GLB: nonzero keeps v as it is instead of writing 1 - v. */
    int gltf_keep_v;
    /** GLB: nonzero says the mesh is Z-up (right-handed, as CAD and STEP
     *  data): it is written rotated into glTF's Y-up frame, (x, y, z) ->
     *  (x, z, -y), positions, normals and tangents alike. */
    int gltf_z_up;
    /** Allocator for temporary memory and geom_meshio_write_memory's
     *  buffer; NULL = libc. */
    const geom_allocator *alloc;
} geom_meshio_write_options;

/**
 * Write m to `path` atomically (see above; the temporary file is
 * ".NAME.XXXXXXXX.geomtmp" in the destination's directory, created with
 * mode 0666 less the umask or the replaced file's mode, and fsync'd before
 * the rename). The format comes from opt->format or the extension.
 *
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL m or path, format not
 * recognised, PLY-only encoding for STL, non-finite coordinates for GLB);
 * GEOM_ERR_IO (the temporary file cannot be created, written or renamed:
 * diag has the system's reason; nothing is left behind); GEOM_ERR_LIMIT (a
 * count beyond what the format can store); GEOM_ERR_NOMEM; the statuses of
 * geom_mesh_clone/geom_mesh_triangulate for formats that need triangles.
 */
GEOM_API geom_status geom_meshio_write(const geom_mesh *m, const char *path,
                              const geom_meshio_write_options *opt, geom_diag *diag);

/**
 * Write m into a new buffer: *data receives it (allocated with opt->alloc,
 * or malloc; free with geom_meshio_buffer_free or, for malloc, free()) and
 * *size its length in bytes. One NUL byte follows the data (not counted in
 * *size, but included in the allocation: free with size + 1), so text
 * output can be used as a C string.
 * opt->format must not be AUTO. On error *data is NULL and *size 0.
 * Statuses as geom_meshio_write without GEOM_ERR_IO.
 */
GEOM_API geom_status geom_meshio_write_memory(const geom_mesh *m, const geom_meshio_write_options *opt,
                                     void **data, size_t *size, geom_diag *diag);

/** Receives geom_meshio_write_stream's output: `size` bytes at `data`, in
 *  order, in pieces of at most 64 KiB. Return GEOM_OK to go on; any other
 *  status stops the write and is returned by it. */
typedef geom_status (*geom_meshio_write_fn)(void *user, const void *data, size_t size);

/**
 * Write m through fn (called with user) as it is produced, without holding
 * the whole output in memory: for a caller with its own destination (a
 * stream, a socket, a temporary file it renames itself). opt->format must
 * not be AUTO. Nothing is passed to fn when the arguments are refused; on a
 * later error part of the output may have been passed (the caller discards
 * it).
 * Statuses as geom_meshio_write_memory, and fn's own status when it fails
 * (diag then says the output could not be written, unless fn set it).
 */
GEOM_API geom_status geom_meshio_write_stream(const geom_mesh *m, const geom_meshio_write_options *opt,
                                     geom_meshio_write_fn fn, void *user, geom_diag *diag);

/** Free a buffer from geom_meshio_write_memory made with the allocator
 *  `alloc` (NULL: libc); `size` is the *size it returned. NULL data is a
 *  no-op. */
GEOM_API void geom_meshio_buffer_free(void *data, size_t size, const geom_allocator *alloc);

/**
 * An indexed polygon soup for geom_meshio_write_soup: what a producer that
 * already knows its connectivity (marching cubes: geom_iso_surface) writes
 * without building a geom_mesh first.
 */
typedef struct geom_meshio_soup {
    size_t n_vertices;
    const double *xyz;          /**< 3 * n_vertices doubles */
    const double *normals;      /**< 3 * n_vertices doubles (per vertex), or NULL */
    size_t n_faces;
    const uint32_t *face_sizes; /**< n_faces sizes (each >= 3), or NULL: all triangles */
    const uint32_t *indices;    /**< 0-based vertex indices, the sum of the sizes */
} geom_meshio_soup;

/**
 * Write the soup s to `path` atomically, as geom_meshio_write does, in OBJ
 * (opt->format OBJ, or AUTO with a .obj name): the same bytes
 * geom_meshio_write gives for the mesh geom_mesh_build makes of the soup
 * when that build needs no repair (vertices in order, then the normals as
 * vn, then each face from its first vertex, "f a//a b//b c//c" with
 * normals), without the half-edge mesh (no memory or time for it). Nothing
 * is repaired or reoriented: the faces are written as given. opt->omit
 * (GEOM_MESHIO_ATTR_NORMAL) and opt->precision apply; other options are
 * ignored.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL s, path or arrays, a format
 * other than OBJ, a face with fewer than 3 vertices or an index past the
 * vertices, a non-finite coordinate: the diag names it; nothing is left
 * behind); GEOM_ERR_LIMIT (2^32 - 1 vertices or more); GEOM_ERR_IO;
 * GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_meshio_write_soup(const geom_meshio_soup *s, const char *path,
                                   const geom_meshio_write_options *opt, geom_diag *diag);

/** geom_meshio_write_soup through fn (as geom_meshio_write_stream):
 *  opt->format must be OBJ. Statuses as geom_meshio_write_soup without
 *  GEOM_ERR_IO, and fn's own status when it fails. */
GEOM_API geom_status geom_meshio_write_soup_stream(const geom_meshio_soup *s,
                                          const geom_meshio_write_options *opt,
                                          geom_meshio_write_fn fn, void *user, geom_diag *diag);

/**
 * One part of an OBJ written part by part through fn (a producer that
 * streams its result, e.g. geom_iso_extract_stream's chunks): with header
 * nonzero the "# written by libgeom" line first, then the part's vertices
 * as v lines (and vn lines with normals), then its faces as f lines. The
 * part's vertex i is the file's vertex first_vertex + i (0-based), and
 * face indices are file numbers (0-based): each below first_vertex +
 * s->n_vertices, so a face may use vertices of earlier parts. The parts
 * of one file read back as the mesh of the whole soup (the same vertices,
 * normals and faces in the same order), with its v and f lines
 * interleaved. Every face is checked before any byte is written. opt as
 * for geom_meshio_write_soup_stream (format OBJ; omit and precision apply).
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL s, arrays or fn, a face of
 * fewer than 3 vertices or an index out of range, a format other than OBJ);
 * GEOM_ERR_LIMIT (first_vertex + n_vertices reaches 2^32 - 1); fn's own
 * status when it fails.
 */
GEOM_API geom_status geom_meshio_write_soup_part(const geom_meshio_soup *s, size_t first_vertex,
                                        int header, const geom_meshio_write_options *opt,
                                        geom_meshio_write_fn fn, void *user, geom_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_MESHIO_H */
