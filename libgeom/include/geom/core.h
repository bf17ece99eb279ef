/*
 * libgeom core: status codes, diagnostics, allocator, vectors and matrices in
 * double precision, transforms and projections, exact geometric predicates,
 * rays and axis-aligned boxes.
 *
 * Conventions (see DESIGN.md):
 *  - every coordinate is a double;
 *  - matrices are column-major, as in OpenGL: element (row r, column c) of a
 *    geom_mat4 is m[4*c + r]; vectors are columns, so transforms compose as
 *    geom_mat4_mul(A, B) = A*B applies B first;
 *  - fallible functions return geom_status (GEOM_OK == 0, errors negative);
 *  - nothing here allocates, prints, or keeps global state; every function is
 *    reentrant.
 *
 * Accuracy: the vector and matrix functions are the straightforward
 * floating-point formulas (a few ulp per operation) unless a function says
 * otherwise; the predicates' signs are exact for all finite input.
 */
#ifndef GEOM_CORE_H
#define GEOM_CORE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Every public function is declared GEOM_API: the shared library is built
 * with -fvisibility=hidden, so only these symbols are exported. */
#ifndef GEOM_API
#  if defined(_WIN32) && defined(GEOM_SHARED_BUILD)
#    define GEOM_API __declspec(dllexport)
#  elif defined(__GNUC__) || defined(__clang__)
#    define GEOM_API __attribute__((visibility("default")))
#  else
#    define GEOM_API
#  endif
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ version */

#define GEOM_VERSION_MAJOR 0
#define GEOM_VERSION_MINOR 1
#define GEOM_VERSION_PATCH 0
#define GEOM_VERSION_STRING "0.1.0"
/** Single integer version: major*10000 + minor*100 + patch. */
#define GEOM_VERSION (GEOM_VERSION_MAJOR * 10000 + GEOM_VERSION_MINOR * 100 + GEOM_VERSION_PATCH)

/** The version string of the library actually linked (may differ from the header's). */
GEOM_API const char *geom_version_string(void);

/* ------------------------------------------------------------------- status */

typedef enum geom_status {
    GEOM_OK = 0,
    GEOM_ERR_NOMEM = -1,        /**< an allocation failed */
    GEOM_ERR_INVALID_ARG = -2,  /**< NULL where not allowed, bad size, NaN/Inf input */
    GEOM_ERR_PARSE = -3,        /**< malformed text or binary input */
    GEOM_ERR_IO = -4,           /**< a file could not be opened, read or written */
    GEOM_ERR_DEGENERATE = -5,   /**< zero-length / zero-area / singular input */
    GEOM_ERR_NONMANIFOLD = -6,  /**< topology the operation cannot represent */
    GEOM_ERR_DOMAIN = -7,       /**< argument outside the function's domain */
    GEOM_ERR_LIMIT = -8         /**< a size or iteration limit was exceeded */
} geom_status;

/** A short, static, human-readable name for a status ("ok", "out of memory", ...).
 *  Unknown values give "unknown status". Never NULL. */
GEOM_API const char *geom_status_str(geom_status s);

/* -------------------------------------------------------------- diagnostics */

#define GEOM_DIAG_MESSAGE_MAX 256

/**
 * What a caller could change to get past a failure, beside the message: the
 * message itself names no option field, so a tool can name its own option.
 */
typedef enum geom_diag_hint {
    GEOM_DIAG_HINT_NONE = 0, /**< nothing to suggest */
    /** an invalid face (fewer than 3 vertices, a vertex repeated) stopped
     *  reading a mesh; geom_mesh_build_options.skip_invalid_faces skips such
     *  faces instead */
    GEOM_DIAG_HINT_SKIP_INVALID_FACES = 1
} geom_diag_hint;

/**
 * Optional diagnostic receiver. Functions taking a `geom_diag *` accept NULL.
 * On failure they fill it: the status, a message, and where input is text or a
 * file, the source name, 1-based line and column (0 when unknown) or, for
 * binary input, the byte offset, and a geom_diag_hint.
 */
typedef struct geom_diag {
    geom_status status;
    char message[GEOM_DIAG_MESSAGE_MAX];
    char source[GEOM_DIAG_MESSAGE_MAX]; /**< file name, "<stdin>", or "" */
    size_t line;                        /**< 1-based; 0 if not applicable */
    size_t column;                      /**< 1-based; 0 if not applicable */
    uint64_t byte_offset;               /**< for binary input; 0 if not applicable */
    geom_diag_hint hint;                /**< GEOM_DIAG_HINT_NONE unless stated */
} geom_diag;

/** Reset a diagnostic to "no error". NULL is a no-op. */
GEOM_API void geom_diag_clear(geom_diag *d);

/** Format `d` as "source:line:column: message" (parts omitted when unknown)
 *  into buf (at most size bytes, always NUL-terminated when size > 0).
 *  Returns the number of characters the full text needs, excluding the NUL. */
GEOM_API size_t geom_diag_format(const geom_diag *d, char *buf, size_t size);

/* ---------------------------------------------------------------- allocator */

/**
 * Optional allocator. A NULL `const geom_allocator *` argument, or a
 * zero-initialised struct, means the C library's malloc/realloc/free.
 * `realloc_fn` may be NULL, in which case reallocation is done by
 * alloc + copy + free. `free_fn` receives the size originally requested.
 */
typedef struct geom_allocator {
    void *(*alloc_fn)(void *user, size_t size);
    void *(*realloc_fn)(void *user, void *ptr, size_t old_size, size_t new_size);
    void (*free_fn)(void *user, void *ptr, size_t size);
    void *user;
} geom_allocator;

/* ------------------------------------------------------------- error report */

/** How geom_error_report::max_error was obtained. */
enum {
    GEOM_ERROR_NONE = 0,     /**< nothing measured (e.g. nothing was approximated) */
    GEOM_ERROR_BOUND = 1,    /**< a guaranteed upper bound (up to rounding) */
    GEOM_ERROR_SAMPLED = 2,  /**< measured at sample points: a lower estimate */
    GEOM_ERROR_ESTIMATE = 3  /**< an a-posteriori estimate (e.g. two quadrature orders) */
};

/**
 * What an approximating function achieved (tessellation, isosurfaces,
 * contours, subdivision toward the limit, root finding, quadrature): the
 * error measure, in the units the function states, how it was measured,
 * the tolerance it worked to, the work done and the time taken. Every
 * approximating operation fills one the same way, and the tools print it
 * the same way (`--json`: an "error" object with these fields).
 */
typedef struct geom_error_report {
    double max_error;   /**< largest error over the pieces (or the total, where stated) */
    double mean_error;  /**< mean over the pieces */
    int method;         /**< GEOM_ERROR_BOUND, GEOM_ERROR_SAMPLED or GEOM_ERROR_ESTIMATE */
    size_t evaluations; /**< function evaluations (or samples) performed */
    /** The tolerance the operation worked to, in the units of max_error
     *  (the effective one, after defaults); 0 when it has none (a fixed
     *  grid, a fixed number of levels). */
    double tolerance;
    size_t pieces;      /**< elements the error was measured over (triangles, vertices, ...) */
    double seconds;     /**< wall-clock time of the operation, the measurement included */
} geom_error_report;

/* ------------------------------------------------------------------ numbers */

/** Buffer size for geom_format_double / geom_format_double_digits (longest
 *  output "-2.2250738585072014e-308" is 24 characters, plus the NUL). */
#define GEOM_DOUBLE_CHARS 32

/**
 * The shortest decimal that reads back as exactly x (Ryu: Ulf Adams, "Ryu:
 * Fast Float-to-String Conversion", PLDI 2018), into buf, NUL-terminated,
 * independent of the locale. Returns the length (at most 24).
 *
 * Syntax: an optional '-', then the n shortest significant digits d1..dn
 * (the ones closest to x among the shortest; ties to even) with decimal
 * exponent X (x = d1.d2..dn * 10^X), written as printf's "%.<P>g" would with
 * P = max(n, 15) and no trailing zeros: fixed notation ("0.001", "12.5",
 * "100000") when -4 <= X < P, else "d1.d2..dne+XX" / "e-XX" with at least
 * two exponent digits ("1e+20", "2.5e-07"). Zero is "0" or "-0". NaN is
 * "nan" and infinities "inf" / "-inf": geom_parse_double reads those back
 * (the mesh readers refuse them as non-finite).
 */
GEOM_API size_t geom_format_double(double x, char buf[GEOM_DOUBLE_CHARS]);

/**
 * x with `digits` significant digits (1..17; larger values mean 17, 0 or
 * negative means geom_format_double's shortest form), correctly rounded, in
 * printf's "%.<digits>g" syntax with '.' as the decimal point whatever the
 * locale. NaN and infinities as in geom_format_double. Returns the length.
 */
GEOM_API size_t geom_format_double_digits(double x, int digits, char buf[GEOM_DOUBLE_CHARS]);

/**
 * Parse a decimal number at the start of [s, end) (no leading spaces, not
 * NUL-terminated), correctly rounded to the nearest double, ties to even
 * (Eisel-Lemire: Daniel Lemire, "Number Parsing at a Gigabyte per Second",
 * Softw. Pract. Exp. 2021; with an exact fallback through a bounded copy for
 * the rare inputs it cannot decide). Any number of digits is accepted.
 *
 * Syntax: [+-]? (digits [. digits?] | . digits) ([eE] [+-]? digits)?, or a
 * C99 hexadecimal float [+-]? 0[xX] (hexdigits [. hexdigits?] | . hexdigits)
 * ([pP] [+-]? digits)?, or [+-]? followed by "inf", "infinity" or "nan" in
 * any case. An exponent letter not followed by digits is not consumed (nor
 * is an "x" without hexadecimal digits after it: "0x" reads as 0). No
 * locale decimal point, no "nan(...)". *stop (if stop is not NULL) receives the end of the
 * longest prefix read (s when nothing is read); callers that want a whole
 * token compare it with end.
 *
 * Returns GEOM_OK (also for the spelled "inf"/"nan", so check isfinite when
 * they are not wanted; values below the subnormal range read as +-0),
 * GEOM_ERR_DOMAIN when a finite spelling overflows (*out = +-infinity),
 * GEOM_ERR_PARSE when no number starts at s (*out = 0), GEOM_ERR_INVALID_ARG
 * for NULL s, end or out, or end < s.
 */
GEOM_API geom_status geom_parse_double(const char *s, const char *end, double *out,
                                       const char **stop);

/* -------------------------------------------------------------------- files */

/**
 * A whole file's bytes, read-only. Regular files are mapped into memory
 * (mmap, MAP_PRIVATE, with a sequential-access hint): no copy, pages are
 * read on first touch. Pipes, terminals and other descriptors are read with
 * read() into an allocated buffer. `data` is not NUL-terminated; it is
 * valid until geom_file_unmap. A mapped file that another process truncates
 * while mapped may fault on access (as with any mapping). The impl_ fields
 * are private.
 */
typedef struct geom_file {
    const unsigned char *data; /**< size bytes (never NULL after a map call) */
    size_t size;
    void *impl_base;
    size_t impl_size;
    int impl_mapped;
    const geom_allocator *impl_alloc;
} geom_file;

/**
 * Map (or read) the file at `path` into *out. alloc (NULL = libc) is used
 * only when the file has to be read. Returns GEOM_OK, GEOM_ERR_IO (cannot
 * open or read, a directory; diag names the path and the system's reason),
 * GEOM_ERR_NOMEM, GEOM_ERR_LIMIT (too large for memory), GEOM_ERR_INVALID_ARG
 * (NULL path or out). On failure *out is empty (size 0).
 */
GEOM_API geom_status geom_file_map(const char *path, const geom_allocator *alloc,
                                   geom_file *out, geom_diag *diag);

/**
 * As geom_file_map, for an open descriptor (e.g. 0 for standard input): a
 * regular file positioned at its start is mapped; anything else is read
 * from its current position to its end. The descriptor stays open and may
 * be closed right after the call. `name` is used in diagnostics.
 */
GEOM_API geom_status geom_file_map_fd(int fd, const char *name, const geom_allocator *alloc,
                                      geom_file *out, geom_diag *diag);

/** Release what geom_file_map / geom_file_map_fd returned. NULL and an
 *  already released or zeroed geom_file are no-ops. */
GEOM_API void geom_file_unmap(geom_file *f);

/**
 * An output file written the way cp writes one, so that nothing of the
 * user's is ever destroyed (the rules of the mesh writers and the tools):
 *  - a path that does not exist, or a regular file: the bytes go to a
 *    temporary file ".NAME.XXXXXXXX.geomtmp" in the same directory (NAME
 *    shortened at a UTF-8 boundary so that the name fits NAME_MAX), created
 *    with the mode (and, where permitted, the owner) of the file it will
 *    replace, or 0666 less the umask; geom_output_commit renames it over the
 *    destination, so a failed or interrupted run never leaves a truncated
 *    file. A symbolic link to a regular file stays a link: the file it
 *    points to is replaced. A file the caller may not write is refused
 *    (permission denied) as cp refuses it;
 *  - a device (/dev/null, /dev/full), a FIFO or socket, or a symbolic link
 *    to one: opened and written through, never replaced;
 *  - a directory, a path ending in '/', or a dangling symbolic link: refused.
 * A stale temporary file (of a killed process) keeps the ".geomtmp" name and
 * is never taken for output. Callers that catch signals may unlink
 * `temporary` (a NUL-terminated path, stable while open) from the handler.
 * The impl_ fields are private. POSIX only.
 */
typedef struct geom_output {
    int fd;          /**< write here (or through geom_output_write); -1 when closed */
    char *temporary; /**< the temporary file while open; NULL when written through */
    char *impl_path, *impl_dest;
    size_t impl_path_size, impl_dest_size, impl_tmp_size;
    const geom_allocator *impl_alloc;
} geom_output;

/**
 * Open the output for `path` by the rules above. alloc (NULL = libc) holds
 * the names. GEOM_OK; GEOM_ERR_IO (refused, or the system's error: diag names
 * the path and the system's reason), GEOM_ERR_NOMEM, GEOM_ERR_INVALID_ARG
 * (NULL or empty path, NULL out). On failure nothing is left behind and *out
 * is closed (fd == -1).
 */
GEOM_API geom_status geom_output_open(const char *path, const geom_allocator *alloc,
                                      geom_output *out, geom_diag *diag);

/** Write n bytes (retrying short writes and EINTR). GEOM_ERR_IO with the
 *  system's reason (ENOSPC is one), GEOM_ERR_INVALID_ARG (not open). */
GEOM_API geom_status geom_output_write(geom_output *out, const void *data, size_t n,
                                       geom_diag *diag);

/**
 * Finish: fsync, close, and rename the temporary file onto the destination
 * (atomically replacing it); a destination written through is only closed.
 * On failure the temporary file is removed and the destination is left as
 * it was. The output is closed either way. GEOM_ERR_IO, GEOM_ERR_INVALID_ARG
 * (not open).
 */
GEOM_API geom_status geom_output_commit(geom_output *out, geom_diag *diag);

/** Abandon: close and remove the temporary file (the destination is left as
 *  it was). NULL, and a closed or zeroed output, are no-ops. */
GEOM_API void geom_output_abort(geom_output *out);

/* ------------------------------------------------------------------ vectors */

typedef struct geom_vec2 { double x, y; } geom_vec2;
typedef struct geom_vec3 { double x, y, z; } geom_vec3;
typedef struct geom_vec4 { double x, y, z, w; } geom_vec4;

GEOM_API geom_vec2 geom_vec2_make(double x, double y);
GEOM_API geom_vec2 geom_vec2_add(geom_vec2 a, geom_vec2 b);
GEOM_API geom_vec2 geom_vec2_sub(geom_vec2 a, geom_vec2 b);
GEOM_API geom_vec2 geom_vec2_scale(geom_vec2 a, double s);
GEOM_API double geom_vec2_dot(geom_vec2 a, geom_vec2 b);
/** z component of the 3D cross product (a.x*b.y - a.y*b.x). */
GEOM_API double geom_vec2_cross(geom_vec2 a, geom_vec2 b);
/** Euclidean length without overflow or underflow (hypot). */
GEOM_API double geom_vec2_length(geom_vec2 a);
/** Unit vector in the direction of a. GEOM_ERR_DEGENERATE if a is zero
 *  (out set to (0,0)), GEOM_ERR_INVALID_ARG if a has NaN/Inf (out set to (0,0)). */
GEOM_API geom_status geom_vec2_normalize(geom_vec2 a, geom_vec2 *out);

GEOM_API geom_vec3 geom_vec3_make(double x, double y, double z);
GEOM_API geom_vec3 geom_vec3_add(geom_vec3 a, geom_vec3 b);
GEOM_API geom_vec3 geom_vec3_sub(geom_vec3 a, geom_vec3 b);
GEOM_API geom_vec3 geom_vec3_scale(geom_vec3 a, double s);
GEOM_API geom_vec3 geom_vec3_neg(geom_vec3 a);
/** a + t*(b - a). */
GEOM_API geom_vec3 geom_vec3_lerp(geom_vec3 a, geom_vec3 b, double t);
GEOM_API double geom_vec3_dot(geom_vec3 a, geom_vec3 b);
GEOM_API geom_vec3 geom_vec3_cross(geom_vec3 a, geom_vec3 b);
/** Euclidean length, scaled so that it neither overflows nor underflows for
 *  any finite input (relative error a few ulp). */
GEOM_API double geom_vec3_length(geom_vec3 a);
/** Unit vector in the direction of a (accurate to a few ulp even for
 *  components near DBL_MAX or subnormal). GEOM_ERR_DEGENERATE if a is the zero
 *  vector, GEOM_ERR_INVALID_ARG if it has NaN/Inf; out is then (0,0,0),
 *  never NaN. */
GEOM_API geom_status geom_vec3_normalize(geom_vec3 a, geom_vec3 *out);
/** Mirror direction: i - 2 (n.i) n, n must be unit length. */
GEOM_API geom_vec3 geom_vec3_reflect(geom_vec3 i, geom_vec3 n);
/**
 * Refraction by Snell's law of the unit incident direction i at a surface with
 * unit normal n (pointing against i, i.e. n.i <= 0) with eta = n1/n2.
 * Returns GEOM_OK with the unit transmitted direction, or GEOM_ERR_DOMAIN on
 * total internal reflection, in which case *out is the reflected direction.
 * GEOM_ERR_INVALID_ARG for NaN/Inf input or eta <= 0.
 */
GEOM_API geom_status geom_vec3_refract(geom_vec3 i, geom_vec3 n, double eta, geom_vec3 *out);

GEOM_API geom_vec4 geom_vec4_make(double x, double y, double z, double w);
/** (x/w, y/w, z/w). GEOM_ERR_DEGENERATE when w == 0, GEOM_ERR_INVALID_ARG
 *  when w is NaN/Inf (out set to (0,0,0) in both cases). */
GEOM_API geom_status geom_vec4_homogeneous_divide(geom_vec4 a, geom_vec3 *out);

/* ----------------------------------------------------------------- matrices */

/** 3x3 matrix, column-major: element (r, c) is m[3*c + r]. */
typedef struct geom_mat3 { double m[9]; } geom_mat3;
/** 4x4 matrix, column-major: element (r, c) is m[4*c + r]. */
typedef struct geom_mat4 { double m[16]; } geom_mat4;

GEOM_API geom_mat3 geom_mat3_identity(void);
GEOM_API geom_mat3 geom_mat3_mul(geom_mat3 a, geom_mat3 b);
GEOM_API geom_vec3 geom_mat3_mul_vec3(geom_mat3 a, geom_vec3 v);
GEOM_API geom_mat3 geom_mat3_transpose(geom_mat3 a);
GEOM_API double geom_mat3_determinant(geom_mat3 a);
/**
 * Inverse by the adjugate. GEOM_ERR_DEGENERATE when the matrix is singular or
 * so ill-conditioned that |det| <= 1e-14 * product of the column norms
 * (Hadamard's bound); *out is then the identity. GEOM_ERR_INVALID_ARG on
 * NaN/Inf. Relative accuracy ~ cond(A) * 1e-16.
 */
GEOM_API geom_status geom_mat3_inverse(geom_mat3 a, geom_mat3 *out);

GEOM_API geom_mat4 geom_mat4_identity(void);
/** a*b: applying the result applies b first, then a. */
GEOM_API geom_mat4 geom_mat4_mul(geom_mat4 a, geom_mat4 b);
GEOM_API geom_vec4 geom_mat4_mul_vec4(geom_mat4 a, geom_vec4 v);
GEOM_API geom_mat4 geom_mat4_transpose(geom_mat4 a);
GEOM_API double geom_mat4_determinant(geom_mat4 a);
/** Inverse by cofactors; the same singularity rule and statuses as
 *  geom_mat3_inverse (threshold on the 4 column norms). */
GEOM_API geom_status geom_mat4_inverse(geom_mat4 a, geom_mat4 *out);
/** Upper-left 3x3 block. */
GEOM_API geom_mat3 geom_mat4_upper3(geom_mat4 a);
/**
 * Normal matrix: the inverse-transpose of the upper-left 3x3 block, which maps
 * surface normals under the affine transform a (normals then need
 * renormalising). GEOM_ERR_DEGENERATE if that block is singular.
 */
GEOM_API geom_status geom_mat4_normal_matrix(geom_mat4 a, geom_mat3 *out);

GEOM_API geom_mat4 geom_mat4_translate(geom_vec3 t);
GEOM_API geom_mat4 geom_mat4_scale(geom_vec3 s);
/**
 * Rotation by `radians` about `axis` through the origin, counter-clockwise
 * when looking from the axis tip toward the origin (right-handed, as
 * glRotate). The axis need not be unit length; GEOM_ERR_DEGENERATE if it is
 * zero (out = identity).
 */
GEOM_API geom_status geom_mat4_rotate(geom_vec3 axis, double radians, geom_mat4 *out);
/** Transform a point (w = 1) with homogeneous divide; GEOM_ERR_DEGENERATE if
 *  the resulting w is 0. */
GEOM_API geom_status geom_mat4_transform_point(geom_mat4 a, geom_vec3 p, geom_vec3 *out);
/** Transform a direction (w = 0): upper 3x3 times v. */
GEOM_API geom_vec3 geom_mat4_transform_dir(geom_mat4 a, geom_vec3 v);
/**
 * View matrix as gluLookAt: camera at eye, looking at center, with `up`
 * projected to the screen's vertical. GEOM_ERR_DEGENERATE if eye == center or
 * up is parallel to the view direction (out = identity).
 */
GEOM_API geom_status geom_mat4_lookat(geom_vec3 eye, geom_vec3 center, geom_vec3 up, geom_mat4 *out);
/**
 * Perspective projection as gluPerspective (OpenGL convention: right-handed
 * eye space looking down -z, clip depth mapped to [-1, 1] for z in
 * [-near, -far]). fovy_radians in (0, pi), aspect > 0, 0 < near < far;
 * otherwise GEOM_ERR_DOMAIN (out = identity).
 */
GEOM_API geom_status geom_mat4_perspective(double fovy_radians, double aspect, double near_z,
                                  double far_z, geom_mat4 *out);
/** Orthographic projection as glOrtho (depth to [-1, 1]). GEOM_ERR_DOMAIN if
 *  left == right, bottom == top or near == far. */
GEOM_API geom_status geom_mat4_ortho(double left, double right, double bottom, double top,
                            double near_z, double far_z, geom_mat4 *out);

/* --------------------------------------------------------------- predicates */

/**
 * Orientation of three 2D points (each 2 doubles): positive if a, b, c are in
 * counter-clockwise order, negative if clockwise, zero if collinear. The sign
 * is exact for all finite input (floating-point filter with an exact
 * fallback built from error-free transformations, after Shewchuk 1997); the
 * magnitude approximates twice the signed area. NaN if any input is NaN/Inf.
 */
GEOM_API double geom_orient2d(const double a[2], const double b[2], const double c[2]);
/**
 * Orientation of four 3D points: positive if d lies below the plane through
 * a, b, c (a, b, c counter-clockwise seen from above), i.e. the sign of
 * det[a-d; b-d; c-d]. Exact sign, magnitude ~ six times the signed volume.
 */
GEOM_API double geom_orient3d(const double a[3], const double b[3], const double c[3],
                     const double d[3]);
/**
 * In-circle test: positive if d lies inside the circle through a, b, c (given
 * counter-clockwise), negative outside, zero on it. Exact sign.
 */
GEOM_API double geom_incircle(const double a[2], const double b[2], const double c[2],
                     const double d[2]);

/**
 * Exact determinant-style helpers used by the barycentric module: the value
 * of orient2d / orient3d rounded to the nearest double (relative error
 * <= 2^-52), at higher cost than the sign-only predicates. The sign is always
 * exact: a value beyond the double range gives +-Inf, a nonzero value below
 * the smallest subnormal gives +-DBL_TRUE_MIN (never 0), and values in the
 * subnormal range are rounded to it. NaN if any input is NaN/Inf.
 *
 * For all the predicates above, when the floating-point filter cannot
 * certify the sign, the returned magnitude is this exactly rounded value
 * (with the same range rules), so a nonzero determinant never returns 0.
 */
GEOM_API double geom_orient2d_exact(const double a[2], const double b[2], const double c[2]);
GEOM_API double geom_orient3d_exact(const double a[3], const double b[3], const double c[3],
                           const double d[3]);

/** Which predicate geom_predicate_many applies. */
typedef enum geom_predicate {
    GEOM_PREDICATE_ORIENT2D = 1,       /**< geom_orient2d: 3 points of 2 doubles */
    GEOM_PREDICATE_ORIENT3D = 2,       /**< geom_orient3d: 4 points of 3 doubles */
    GEOM_PREDICATE_INCIRCLE = 3,       /**< geom_incircle: 4 points of 2 doubles */
    GEOM_PREDICATE_ORIENT2D_EXACT = 4, /**< geom_orient2d_exact: 3 points of 2 doubles */
    GEOM_PREDICATE_ORIENT3D_EXACT = 5  /**< geom_orient3d_exact: 4 points of 3 doubles */
} geom_predicate;

/**
 * The predicate `kind` over n rows in one call (for bindings and loops over
 * arrays). pts: the point arrays in the single function's argument order
 * (3 or 4 of them; pts[3] is ignored for the 3-point predicates); row i of
 * argument j starts at pts[j] + i * strides[j] (strides in doubles: the
 * point size for one point per row, 0 for the same point in every row).
 * out: n doubles, each exactly the single function's result for that row
 * (bitwise, sign exact; NaN for a row with NaN/Inf input).
 * Returns GEOM_OK, or GEOM_ERR_INVALID_ARG for a NULL array or a bad kind
 * with n > 0 (nothing written).
 */
GEOM_API geom_status geom_predicate_many(geom_predicate kind, size_t n,
                                         const double *const pts[4], const size_t strides[4],
                                         double *out);

/* ------------------------------------------------------------ rays and boxes */

/** A ray origin + t*dir for t in [tmin, tmax]. dir need not be unit length. */
typedef struct geom_ray {
    geom_vec3 origin;
    geom_vec3 dir;
    double tmin;
    double tmax;
} geom_ray;

/** Axis-aligned box; empty when any min > max (geom_aabb_empty()). */
typedef struct geom_aabb {
    geom_vec3 min;
    geom_vec3 max;
} geom_aabb;

/** The empty box (min = +inf, max = -inf), the identity for union. */
GEOM_API geom_aabb geom_aabb_empty(void);
GEOM_API bool geom_aabb_is_empty(geom_aabb b);
GEOM_API geom_aabb geom_aabb_extend(geom_aabb b, geom_vec3 p);
GEOM_API geom_aabb geom_aabb_union(geom_aabb a, geom_aabb b);
GEOM_API bool geom_aabb_contains(geom_aabb b, geom_vec3 p);

/**
 * Slab test (Kay-Kajiya with the NaN-safe ordering of Williams et al. 2005 and
 * the conservative rounding of Ize 2013). Returns true and the parametric
 * interval [*t0, *t1] (either pointer may be NULL) of the ray inside the box,
 * clipped to [tmin, tmax]. Zero direction components are handled (the ray is
 * parallel to that slab: inside iff the origin is), a ray through an edge or
 * corner counts as a hit, and NaN in the ray or box gives false, never a
 * spurious hit. The interval is widened by 2*gamma(3) so that a ray tangent to
 * a face is never lost to rounding.
 */
GEOM_API bool geom_ray_aabb(const geom_ray *r, geom_aabb b, double *t0, double *t1);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_CORE_H */
