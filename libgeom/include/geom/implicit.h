/*
 * libgeom implicit: implicit functions f(x, y, z) and their isolines.
 *
 *  - Expressions: a small language over x, y, z (and t) compiled once into a
 *    flat program (a postfix tape run by a loop, no recursion at evaluation
 *    time) that gives the value, the exact gradient (forward-mode dual
 *    numbers) and interval bounds over a box.
 *  - Fields: a plain callback interface (value, optional gradient, user
 *    pointer, optional batches and bounds) for user functions, with
 *    adapters from expressions and from sampled volumes: the one field
 *    type, also taken by marching cubes (geom/iso.h).
 *  - Sampled volumes: dense float or double grids (geom_implicit_grid, the
 *    one grid description) read from raw files and NRRD, MetaImage,
 *    INRIMAGE and NIfTI, evaluated by trilinear interpolation.
 *  - Marching squares: isolines of f(x, y, z0) on a regular grid, saddles
 *    resolved by the asymptotic decider, vertices shared between cells and
 *    refined on their edge by safeguarded root finding, joined into
 *    polylines.
 *
 * Sign convention everywhere: f < 0 is inside, f > 0 outside. Contouring
 * at an isovalue iso (here and in geom/iso.h) counts f <= iso as inside
 * and f > iso as outside: a sample exactly on the isovalue is inside, in
 * 2D and 3D alike (the level set at iso + epsilon).
 *
 * Nothing here keeps global state or prints. A compiled expression and a
 * volume are immutable after creation (except geom_implicit_expr_set_time),
 * so any number of threads may evaluate them at once.
 *
 * ---------------------------------------------------------------- language
 *
 * Grammar (whitespace, including newlines, is ignored between tokens):
 *
 *     expr    := term (('+' | '-') term)*
 *     term    := unary (('*' | '/') unary)*
 *     unary   := ('-' | '+') unary | power
 *     power   := primary ('^' unary)?          right associative:
 *                                              2^3^2 = 2^9, -x^2 = -(x^2),
 *                                              x^-1 is allowed
 *     primary := NUMBER | NAME | NAME '(' [expr (',' expr)*] ')' | '(' expr ')'
 *
 * NUMBER is decimal with optional fraction and exponent ("2", "0.5", ".5",
 * "1e-3", "1.E+2"); it is read as strtod reads it in the C locale (correctly
 * rounded). Names are case-sensitive.
 *
 * Variables: x, y, z, t (t is a parameter set with geom_implicit_expr_set_time;
 * the gradient is with respect to x, y, z only). Constants: pi, e.
 *
 * Functions (all arguments are expressions; n-ary means two or more):
 *   sqrt(a) abs(a) sin(a) cos(a) tan(a) exp(a) log(a)   (log is natural)
 *   pow(a, b) = a ^ b (a constant integer exponent is evaluated as an exact
 *       integer power, so (-2)^3 = -8; otherwise as C's pow)
 *   min(a, b, ...) max(a, b, ...)  n-ary
 *   clamp(v, lo, hi) = min(max(v, lo), hi)
 *   atan2(y, x)  in (-pi, pi]
 *
 * Primitives (negative inside; c = (cx, cy, cz) is a centre, p - c the
 * point relative to it, q = p - c; every distance is Euclidean):
 *   sphere(r), sphere(cx, cy, cz, r)
 *       |q| - r: the exact signed distance.
 *   ellipsoid(a, b, c), ellipsoid(cx, cy, cz, a, b, c)
 *       semi-axes a, b, c along x, y, z: (|(qx/a, qy/b, qz/c)| - 1) * min(a, b, c),
 *       which is exact for a sphere, zero exactly on the ellipsoid, and a
 *       1-Lipschitz lower bound of the distance otherwise.
 *   torus(R, r), torus(cx, cy, cz, R, r)
 *       axis z, major radius R, minor radius r:
 *       |(sqrt(qx^2 + qy^2) - R, qz)| - r, the exact signed distance.
 *   box(hx, hy, hz), box(cx, cy, cz, hx, hy, hz)
 *       half-extents h: with d = |q| - h (componentwise),
 *       |max(d, 0)| + min(max(dx, dy, dz), 0), the exact signed distance.
 *   cylinder(r, h), cylinder(cx, cy, cz, r, h)
 *       capped, axis z, radius r, half-height h: with
 *       d = (sqrt(qx^2 + qy^2) - r, |qz| - h),
 *       |max(d, 0)| + min(max(d1, d2), 0), the exact signed distance.
 *   plane(nx, ny, nz, d)
 *       (n . p - d) / |n|: the half-space n . p <= d is inside; the exact
 *       signed distance.
 *   capsule(ax, ay, az, bx, by, bz, r)
 *       distance to the segment ab minus r (a sphere when a == b), exact.
 *   gyroid(), gyroid(s), gyroid(s, th)
 *       g = sin(sx)cos(sy) + sin(sy)cos(sz) + sin(sz)cos(sx); gyroid() is g
 *       with s = 1, gyroid(s) is g / s (the gyroid of period 2 pi / s, its
 *       labyrinth with g < 0 inside), gyroid(s, th) is |g| / s - th, a
 *       sheet of half-thickness about th around the surface.
 * CSG (a, b are any expressions, treated as signed distances):
 *   union(a, b, ...) = min, intersection(a, b, ...) = max (n-ary),
 *   difference(a, b, ...) = max(a, -b, ...),
 *   smooth_union(a, b, k) = smin(a, b, k),
 *   smooth_intersection(a, b, k) = -smin(-a, -b, k),
 *   smooth_difference(a, b, k) = -smin(-a, b, k),
 *   with the polynomial (quadratic) smooth minimum of Quilez:
 *   smin(a, b, k) = min(a, b) - max(k - |a - b|, 0)^2 / (4k), which is
 *   min(a, b) when |a - b| >= k and for k <= 0.
 *
 * Derivative conventions (the gradient is exact wherever f is
 * differentiable; at kinks a one-sided choice is made):
 *   - min(a, b) takes a's gradient when a <= b, max(a, b) when a >= b (ties
 *     go to the first argument; for the n-ary forms, the leftmost argument
 *     among equal ones); clamp(v, lo, hi) takes v's gradient when
 *     lo <= v <= hi;
 *   - abs(a) at a == 0 has derivative 0 (the minimal-norm subgradient);
 *   - a derivative that would be (infinite or NaN) * 0, e.g. sqrt at 0 where
 *     the argument has zero derivative (the centre of a sphere), is 0;
 *   - atan2 at the origin has derivative 0.
 *
 * Non-finite values: NaN propagates through every operation, including min,
 * max, clamp (unlike C's fmin) and powers (unlike C's pow(1, NaN) and
 * pow(NaN, 0), which are 1); sqrt and log of negative numbers, and
 * pow of a negative base with a non-integer exponent, give NaN; division by
 * zero gives +-inf or NaN as in IEEE 754.
 *
 * Interval bounds: each operation maps intervals to an interval enclosing
 * the values the point evaluation can produce at any point of the box
 * where that value is finite. Results of + - * / are rounded outward by one
 * ulp (nextafter); sqrt likewise (it is correctly rounded); exp, log, pow,
 * sin, cos, tan and atan2 results are widened by 4 ulp relative plus
 * nextafter (glibc documents at most 1-2 ulp for these). Even integer
 * powers and abs are never negative; division by an interval containing 0
 * gives [-inf, inf]; sqrt and log use only the part of the interval inside
 * their domain. An interval [NaN, NaN] means no point of the box has a
 * defined value. The bounds are not tight (the dependency problem of
 * interval arithmetic: x - x gives [-w, w]).
 *
 * Limits: the text is at most max_length bytes; parentheses, calls and
 * unary operators nest at most max_depth deep (the parser's recursion is
 * bounded by it); evaluation uses a fixed stack of GEOM_IMPLICIT_STACK_MAX
 * slots. Exceeding any of these is GEOM_ERR_LIMIT.
 */
#ifndef GEOM_IMPLICIT_H
#define GEOM_IMPLICIT_H

#include "geom/core.h"
#include "geom/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif


/* ------------------------------------------------------------- expressions */

/** Slots of the fixed evaluation stack; a program needing more is rejected. */
#define GEOM_IMPLICIT_STACK_MAX 512
/** Default and largest accepted geom_implicit_expr_options::max_depth. */
#define GEOM_IMPLICIT_DEPTH_DEFAULT 64
#define GEOM_IMPLICIT_DEPTH_MAX 1000
/** Default geom_implicit_expr_options::max_length (bytes). */
#define GEOM_IMPLICIT_LENGTH_DEFAULT 65536

/** A compiled expression (opaque). */
typedef struct geom_implicit_expr geom_implicit_expr;

/** Compilation options; a zero-initialised struct (or NULL) gives the defaults. */
typedef struct geom_implicit_expr_options {
    /** Allocator for the program; NULL = libc. It must outlive the expression. */
    const geom_allocator *alloc;
    /** Longest accepted text in bytes; 0 = GEOM_IMPLICIT_LENGTH_DEFAULT. */
    size_t max_length;
    /** Deepest nesting of parentheses, calls and unary operators;
     *  0 = GEOM_IMPLICIT_DEPTH_DEFAULT; values above GEOM_IMPLICIT_DEPTH_MAX
     *  are treated as GEOM_IMPLICIT_DEPTH_MAX. */
    size_t max_depth;
} geom_implicit_expr_options;

/**
 * Parse and compile `len` bytes of `text` (need not be NUL-terminated, never
 * read beyond len; a NUL byte in it is an error) into *out. Constant
 * subexpressions are folded.
 *
 * Statuses: GEOM_OK; GEOM_ERR_PARSE for a syntax error, an unknown name or a
 * wrong number of arguments: diag gets line 1 (or the line of a multi-line
 * text), the 1-based column of the offending token and a message naming
 * what was found and what was expected ("expected ')' to close '(' at
 * column 3, found end of input", "unknown function 'spher'", "'sphere'
 * takes 1 or 4 arguments, got 2"); GEOM_ERR_LIMIT when the text is longer
 * than max_length, nests deeper than max_depth or needs more than
 * GEOM_IMPLICIT_STACK_MAX stack slots (diag has the column);
 * GEOM_ERR_INVALID_ARG for NULL text (with len > 0) or NULL out;
 * GEOM_ERR_NOMEM. On error *out is NULL. diag's source is "expression".
 */
GEOM_API geom_status geom_implicit_expr_compile(const char *text, size_t len,
                                       const geom_implicit_expr_options *opt,
                                       geom_implicit_expr **out, geom_diag *diag);

/** Free a compiled expression. NULL is a no-op. */
GEOM_API void geom_implicit_expr_destroy(geom_implicit_expr *e);

/** Set the value of the variable t (initially 0). Not to be called while
 *  other threads evaluate e. */
GEOM_API void geom_implicit_expr_set_time(geom_implicit_expr *e, double t);

/** Number of instructions of the compiled program (after constant folding). */
GEOM_API size_t geom_implicit_expr_size(const geom_implicit_expr *e);

/** Bits of geom_implicit_expr_variables(). */
#define GEOM_IMPLICIT_VAR_X 1u
#define GEOM_IMPLICIT_VAR_Y 2u
#define GEOM_IMPLICIT_VAR_Z 4u
#define GEOM_IMPLICIT_VAR_T 8u
/** Which variables the expression reads (GEOM_IMPLICIT_VAR_* bits). */
GEOM_API unsigned geom_implicit_expr_variables(const geom_implicit_expr *e);

/**
 * f(p) for p = 3 doubles (x, y, z). Accuracy: each operation is the
 * correctly rounded IEEE operation or the C library's function (a few ulp),
 * so the error is that of evaluating the written formula in double
 * precision. Non-finite values follow the rules above.
 */
GEOM_API double geom_implicit_expr_eval(const geom_implicit_expr *e, const double p[3]);

/**
 * f at n points: p holds 3*n doubles (point i at p[3i..3i+2]), out receives
 * n doubles, each exactly what geom_implicit_expr_eval gives (the program
 * runs over blocks of 64 points, which amortises the interpreter's
 * dispatch: several times faster than n single evaluations for long
 * programs). From 2^19 points on, out is written with non-temporal stores
 * (it is not left in the caches). NULL e or p (n > 0) fills out with NaN;
 * NULL out is a no-op.
 */
GEOM_API void geom_implicit_expr_eval_many(const geom_implicit_expr *e, size_t n, const double *p,
                                  double *out);

/**
 * f(p) (returned, the same value as geom_implicit_expr_eval) and its exact
 * gradient in grad (3 doubles) by forward-mode dual numbers, with the kink
 * conventions above.
 */
GEOM_API double geom_implicit_expr_eval_grad(const geom_implicit_expr *e, const double p[3],
                                    double grad[3]);

/**
 * Values and exact gradients at n points: p holds 3*n doubles, values
 * receives n doubles and grads (may be NULL) 3*n, each exactly what
 * geom_implicit_expr_eval_grad gives: distance-shaped programs
 * (sqrt(x*x + y*y + z*z) - r, x^2 + y^2 + z^2, sphere(r), ...) straight
 * from the points in vectorised loops, other programs without primitives
 * in blocks of 32 points through a plan made once per call, the rest 16
 * points at a time. NULL e or p (n > 0) fills the outputs with NaN; NULL
 * values is a no-op.
 */
GEOM_API void geom_implicit_expr_eval_grad_many(const geom_implicit_expr *e, size_t n,
                                                const double *p, double *values, double *grads);

/**
 * Interval bounds of f over the box lo..hi (3 doubles each, lo <= hi
 * componentwise, infinite bounds allowed): out[0] <= f(p) <= out[1] for
 * every p in the box where f(p) is finite, as computed by
 * geom_implicit_expr_eval (see "Interval bounds" above). out is
 * {NaN, NaN} when f is defined nowhere in the box.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG for NULL pointers, NaN bounds or
 * lo > hi (out set to {NaN, NaN}).
 */
GEOM_API geom_status geom_implicit_expr_eval_interval(const geom_implicit_expr *e, const double lo[3],
                                             const double hi[3], double out[2]);

/**
 * geom_implicit_expr_eval_interval plus definedness: out as there, and
 * *defined = 1 when, in addition, f is finite at every point of the box
 * (no NaN and no infinity as computed by geom_implicit_expr_eval), so that
 * out[0] <= f(p) <= out[1] holds at every p of the box without exception;
 * 0 when some point may give NaN or an infinity (the test is conservative:
 * it says 0 whenever an intermediate interval is unbounded, or reaches
 * outside the domain of sqrt, log or a non-integer power). Used to skip
 * regions of a grid the level set provably does not cross
 * (geom_implicit_field::bounds).
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG as geom_implicit_expr_eval_interval
 * or for NULL defined (*defined 0, out {NaN, NaN}).
 */
GEOM_API geom_status geom_implicit_expr_eval_bounds(const geom_implicit_expr *e, const double lo[3],
                                                   const double hi[3], double out[2], int *defined);

/**
 * geom_implicit_expr_eval_bounds over n boxes: box i is lo[3i..3i+2] ..
 * hi[3i..3i+2] (lo and hi 3*n doubles); out receives 2*n doubles (box i's
 * lower and upper bound at 2i, 2i+1) and defined n ints, each exactly what
 * geom_implicit_expr_eval_bounds gives for the box (an invalid box, with a
 * NaN bound or lo > hi, gets {NaN, NaN} and 0). One call for many boxes:
 * bindings pay the call overhead once. Reentrant.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG for NULL pointers with n > 0
 * (nothing written) or when some box is invalid (every box written).
 */
GEOM_API geom_status geom_implicit_expr_eval_bounds_many(const geom_implicit_expr *e, size_t n,
                                                        const double *lo, const double *hi,
                                                        double *out, int *defined);

/* ------------------------------------------------------------------ fields */

/** Value of a field at p (3 doubles). */
typedef double (*geom_implicit_value_fn)(void *user, const double p[3]);
/** Value of a field at p (returned) and its gradient in grad (3 doubles).
 *  (Consumers that need only the gradient ignore the returned value; it
 *  must still be the field's value at p.) */
typedef double (*geom_implicit_grad_fn)(void *user, const double p[3], double grad[3]);
/** Values at n points: p holds 3*n doubles (x, y, z of point i at
 *  p[3i..3i+2]), out receives n doubles. Must give exactly what value()
 *  gives at each point. Marching cubes calls it with the nodes of one grid
 *  row at a time (constant y and z, increasing x). */
typedef void (*geom_implicit_values_fn)(void *user, size_t n, const double *p, double *out);
/** Values and gradients at n points: p holds 3*n doubles, values receives
 *  n doubles and grads 3*n. Must give exactly what value() and gradient()
 *  give at each point. */
typedef void (*geom_implicit_gradients_fn)(void *user, size_t n, const double *p, double *values,
                                           double *grads);
/** Bounds of the field over the box lo..hi (3 doubles each, lo <= hi):
 *  return nonzero only when out[0] <= value(p) <= out[1] at EVERY point p
 *  of the box that value() can be called with, value() is never NaN there,
 *  and out holds no NaN; return 0 when that cannot be guaranteed (out is
 *  then ignored). Marching cubes uses it to skip the blocks of the grid
 *  that the surface provably does not cross. */
typedef int (*geom_implicit_bounds_fn)(void *user, const double lo[3], const double hi[3],
                                       double out[2]);

/**
 * A scalar field given by callbacks: the one field type of the library,
 * taken by marching squares (geom_implicit_contour) and marching cubes
 * (geom_iso_extract; geom_iso_field is the same type). Only `value` is
 * required; the others are optional and, except `gradient` and `exact`,
 * for speed only (a consumer that does not use one ignores it). A
 * zero-initialised struct with `value` set is a valid field. The callbacks
 * must be safe to call concurrently if the consumer is parallel.
 *
 * Inside convention (the same in 2D and 3D): a point is inside when
 * f <= iso and outside when f > iso (NaN: see each consumer). Equivalently
 * the contour extracted is the level set at iso + epsilon for an
 * infinitesimal epsilon > 0: grid values exactly equal to iso are inside.
 * The positional order of the first four members (value, gradient, user,
 * exact) is kept from earlier versions.
 */
typedef struct geom_implicit_field {
    geom_implicit_value_fn value;    /**< required */
    geom_implicit_grad_fn gradient;  /**< optional (NULL: central differences where needed) */
    void *user;                      /**< passed to every callback */
    /** Nonzero when value() is the exact function (an expression or a
     *  user formula) rather than an interpolant of samples: root refinement
     *  on edges (GEOM_IMPLICIT_REFINE_AUTO) and the error measure of
     *  marching cubes (GEOM_ISO_ERROR_AUTO) then apply. */
    int exact;
    geom_implicit_values_fn values;       /**< optional batch of values */
    /** optional batch of values and gradients (used with `gradient`) */
    geom_implicit_gradients_fn gradients;
    /** optional rigorous bounds over a box: with it, geom_iso_extract
     *  samples only the blocks of the grid the surface may cross (see
     *  geom_iso_options::dense); the output is the same. */
    geom_implicit_bounds_fn bounds;
} geom_implicit_field;

/** Callbacks over a compiled expression (user = the geom_implicit_expr *):
 *  the same as geom_implicit_expr_eval / geom_implicit_expr_eval_grad. */
GEOM_API double geom_implicit_expr_value_cb(void *user, const double p[3]);
GEOM_API double geom_implicit_expr_grad_cb(void *user, const double p[3], double grad[3]);

/** Fill *out with e's callbacks: value (geom_implicit_expr_eval), gradient
 *  (exact, dual numbers), values (geom_implicit_expr_eval_many), gradients
 *  (geom_implicit_expr_eval_grad_many), bounds (geom_implicit_expr_eval_bounds,
 *  defined boxes only) and exact = 1. e must outlive the field. NULL out is
 *  a no-op. */
GEOM_API void geom_implicit_field_from_expr(const geom_implicit_expr *e, geom_implicit_field *out);

/** Root refinement of vertices on their grid edges:
 *  geom_implicit_contour_options::refine and geom_iso_options::refine.
 *  The members are `int`; 0 (AUTO) is the default of both. */
typedef enum geom_implicit_refine {
    GEOM_IMPLICIT_REFINE_AUTO = 0,   /**< refine when field->exact */
    GEOM_IMPLICIT_REFINE_ALWAYS = 1, /**< refine whatever the field is */
    GEOM_IMPLICIT_REFINE_NEVER = 2   /**< linear interpolation only */
} geom_implicit_refine;

/* ----------------------------------------------------------------- volumes */

/** Sample type of a dense grid or volume in memory: the one scalar-type
 *  enum (geom_iso_scalar and GEOM_ISO_SCALAR_* are aliases of it). */
typedef enum geom_implicit_scalar {
    GEOM_IMPLICIT_SCALAR_F32 = 1, /**< IEEE 754 binary32 */
    GEOM_IMPLICIT_SCALAR_F64 = 2  /**< IEEE 754 binary64 */
} geom_implicit_scalar;

/**
 * A dense sampled grid: the one description of one, used by volumes
 * (geom_implicit_volume_create, geom_implicit_volume_get_desc), the
 * trilinear interpolator (geom_implicit_samples_value) and marching cubes
 * over samples (geom_iso_extract_grid). geom_implicit_volume_desc and
 * geom_iso_grid are the same type.
 * Sample (i, j, k) sits at origin + (i*spacing[0], j*spacing[1],
 * k*spacing[2]) and is element i + dims[0]*(j + dims[1]*k) of the data
 * (x fastest). Zero-initialised fields take defaults where stated.
 */
typedef struct geom_implicit_grid {
    size_t dims[3];            /**< samples per axis, each >= 1 */
    geom_implicit_scalar type; /**< required (0 is invalid) */
    /** the samples, borrowed (dims[0]*dims[1]*dims[2] floats or doubles
     *  as type says), in the machine's byte order. Read by the iso grid
     *  functions; geom_implicit_volume_create ignores it (the volume owns
     *  its samples) and geom_implicit_volume_get_desc sets it to the
     *  volume's. */
    const void *data;
    double spacing[3];         /**< > 0 and finite; 0 = 1 */
    double origin[3];          /**< finite; default 0 */
    /** Deprecated (only geom_implicit_volume_read_raw reads it): nonzero =
     *  the raw file's samples are big-endian. Ignored everywhere else. */
    int big_endian;
} geom_implicit_grid;

/** Deprecated alias of geom_implicit_grid (the volume description of
 *  earlier versions; its members keep their names and meaning). */
typedef struct geom_implicit_grid geom_implicit_volume_desc;

/**
 * Trilinear interpolation at p (3 doubles) of borrowed samples `data`
 * (dims[0]*dims[1]*dims[2] floats or doubles as d->type says; d->spacing 0
 * means 1; big_endian is ignored): the library's one interpolator, used by
 * geom_implicit_volume_eval and geom_iso_grid_value. Points outside the
 * sample box are clamped onto it; along an axis the value is
 * (1 - t) a + t b, nested x, then y, then z, and exactly a (b) at t = 0
 * (t = 1) without reading the other end, so a sample position gives the
 * stored sample exactly and a NaN neighbour does not leak into it. NULL
 * data means d->data. NaN coordinates, NULL d, or no data give NaN.
 */
GEOM_API double geom_implicit_samples_value(const geom_implicit_grid *d, const void *data,
                                            const double p[3]);

/**
 * Gradient at p into grad (3 doubles) of the same samples: the trilinear
 * interpolation of per-sample central differences (s[i+1] - s[i-1]) /
 * (2 spacing), one-sided on the border, 0 along an axis with one sample.
 * NULL data means d->data. NaN coordinates, NULL d or no data give NaN
 * components; NULL grad is a no-op.
 */
GEOM_API void geom_implicit_samples_gradient(const geom_implicit_grid *d, const void *data,
                                             const double p[3], double grad[3]);

/** A dense sampled volume (opaque). */
typedef struct geom_implicit_volume geom_implicit_volume;

/**
 * A new volume with every sample 0 (fill it through geom_implicit_volume_data).
 * Statuses: GEOM_ERR_INVALID_ARG (NULL desc/out, a zero dimension, a bad
 * type, a non-finite origin or a spacing that is negative or non-finite);
 * GEOM_ERR_LIMIT when the sample count or byte size overflows size_t;
 * GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_implicit_volume_create(const geom_implicit_grid *desc,
                                        const geom_allocator *alloc,
                                        geom_implicit_volume **out);

/**
 * Deprecated: geom_implicit_volume_read with format GEOM_IMPLICIT_VOLUME_RAW
 * (this function is a thin wrapper of it). Reads a raw volume:
 * desc->dims[0]*dims[1]*dims[2] samples of desc->type (F32 or F64),
 * little-endian (big-endian with desc->big_endian), x fastest, no header,
 * placed by desc->spacing and desc->origin. The file's size is checked
 * against the dims before anything is allocated: it must be exactly the
 * expected number of bytes.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (as geom_implicit_volume_create,
 * NULL path); GEOM_ERR_IO (cannot open or read: diag has the reason);
 * GEOM_ERR_PARSE (wrong file size: diag says both sizes);
 * GEOM_ERR_LIMIT; GEOM_ERR_NOMEM. NaN and infinite samples are kept.
 */
GEOM_API geom_status geom_implicit_volume_read_raw(const char *path, const geom_implicit_grid *desc,
                                          const geom_allocator *alloc,
                                          geom_implicit_volume **out, geom_diag *diag);

/**
 * Deprecated: geom_implicit_volume_read with format
 * GEOM_IMPLICIT_VOLUME_NRRD and no inflate callback (this function is a
 * thin wrapper of it; see there for what is read: every NRRD sample type
 * and the raw, ascii and hex encodings, attached or detached data).
 * gzip- and bzip2-encoded data are GEOM_ERR_PARSE here (no decompressor is
 * passed: call geom_implicit_volume_read with one).
 * Statuses: GEOM_OK; GEOM_ERR_IO; GEOM_ERR_PARSE (diag: file, line and
 * column of the bad header field, or the byte offset for short data);
 * GEOM_ERR_LIMIT; GEOM_ERR_NOMEM; GEOM_ERR_INVALID_ARG for NULL arguments.
 */
GEOM_API geom_status geom_implicit_volume_read_nrrd(const char *path, const geom_allocator *alloc,
                                           geom_implicit_volume **out, geom_diag *diag);

/**
 * Deprecated: geom_implicit_volume_read_memory with format
 * GEOM_IMPLICIT_VOLUME_NRRD and no inflate callback (a thin wrapper of
 * it), from `size` bytes at `data` (never read beyond size) holding a NRRD
 * file with attached data; source_name (NULL: "<memory>") names it in
 * diagnostics. A detached header is GEOM_ERR_PARSE.
 */
GEOM_API geom_status geom_implicit_volume_read_nrrd_memory(const void *data, size_t size,
                                                  const char *source_name,
                                                  const geom_allocator *alloc,
                                                  geom_implicit_volume **out, geom_diag *diag);

/** Free a volume. NULL is a no-op. */
GEOM_API void geom_implicit_volume_destroy(geom_implicit_volume *v);

/** The volume's shape (spacing filled in, never 0; big_endian 0; data =
 *  the volume's samples, borrowed). */
GEOM_API void geom_implicit_volume_get_desc(const geom_implicit_volume *v, geom_implicit_grid *out);

/** The samples: dims[0]*dims[1]*dims[2] floats or doubles (by type), x
 *  fastest, in the machine's byte order. */
GEOM_API void *geom_implicit_volume_data(geom_implicit_volume *v);
GEOM_API const void *geom_implicit_volume_cdata(const geom_implicit_volume *v);

/** Sample (i, j, k) as a double; NaN when out of range. */
GEOM_API double geom_implicit_volume_at(const geom_implicit_volume *v, size_t i, size_t j, size_t k);

/** The box spanned by the samples: origin .. origin + (dims - 1) * spacing. */
GEOM_API geom_aabb geom_implicit_volume_bounds(const geom_implicit_volume *v);

/**
 * Trilinear interpolation of the samples at p (3 doubles). Points outside
 * the sample box are clamped onto it (the field is extended constantly
 * along the box's normals); NaN coordinates give NaN. Exact at sample
 * positions.
 */
GEOM_API double geom_implicit_volume_eval(const geom_implicit_volume *v, const double p[3]);

/**
 * The trilinear value (as geom_implicit_volume_eval) and a gradient: the
 * trilinear interpolation of the per-sample central-difference gradients
 * ((s[i+1] - s[i-1]) / (2 spacing), one-sided at the border, 0 along an
 * axis with one sample). Second-order accurate at samples for smooth
 * data; outside the box the clamped point's gradient.
 */
GEOM_API double geom_implicit_volume_eval_grad(const geom_implicit_volume *v, const double p[3],
                                      double grad[3]);

/** Callbacks over a volume (user = the geom_implicit_volume *). */
GEOM_API double geom_implicit_volume_value_cb(void *user, const double p[3]);
GEOM_API double geom_implicit_volume_grad_cb(void *user, const double p[3], double grad[3]);

/** Fill *out with v's callbacks (exact = 0). v must outlive the field. */
GEOM_API void geom_implicit_field_from_volume(const geom_implicit_volume *v, geom_implicit_field *out);

/**
 * Which side of iso is v's inside, detected from the samples on the grid's
 * six faces (taken to lie outside): *above = 1 (f >= iso is inside, the
 * value GEOM_ISO_INSIDE_ABOVE of iso.h: a CT volume, dense inside) when
 * more than half of them are < iso, else 0 (f <= iso inside,
 * GEOM_ISO_INSIDE_BELOW: a distance field, negative inside). below and
 * total (each may be NULL) receive the number of face samples < iso and of
 * face samples. The one detection behind geom-iso's and the scene files'
 * default. GEOM_ERR_INVALID_ARG for NULL v or a NaN iso.
 */
GEOM_API geom_status geom_implicit_volume_detect_inside(const geom_implicit_volume *v, double iso,
                                                        int *above, size_t *below, size_t *total);

/* ---------------------------------------------------- volume file formats */

/** Sample type of a volume file. On reading, 8- and 16-bit integers and
 *  float32 become a GEOM_IMPLICIT_SCALAR_F32 volume, 32-bit integers and
 *  float64 a GEOM_IMPLICIT_SCALAR_F64 one: every value is kept exactly. */
typedef enum geom_implicit_sample {
    GEOM_IMPLICIT_SAMPLE_U8 = 1,  /**< unsigned 8-bit */
    GEOM_IMPLICIT_SAMPLE_I8 = 2,  /**< signed 8-bit (two's complement) */
    GEOM_IMPLICIT_SAMPLE_U16 = 3, /**< unsigned 16-bit */
    GEOM_IMPLICIT_SAMPLE_I16 = 4, /**< signed 16-bit */
    GEOM_IMPLICIT_SAMPLE_U32 = 5, /**< unsigned 32-bit */
    GEOM_IMPLICIT_SAMPLE_I32 = 6, /**< signed 32-bit */
    GEOM_IMPLICIT_SAMPLE_F32 = 7, /**< IEEE 754 binary32 */
    GEOM_IMPLICIT_SAMPLE_F64 = 8  /**< IEEE 754 binary64 */
} geom_implicit_sample;

/** Volume file formats for geom_implicit_volume_read. */
typedef enum geom_implicit_volume_format {
    GEOM_IMPLICIT_VOLUME_AUTO = 0,      /**< by content (magic), then raw if dims are given */
    GEOM_IMPLICIT_VOLUME_RAW = 1,       /**< headerless samples described by the options */
    GEOM_IMPLICIT_VOLUME_NRRD = 2,      /**< Teem NRRD (.nrrd, .nhdr) */
    GEOM_IMPLICIT_VOLUME_METAIMAGE = 3, /**< ITK MetaImage (.mha, .mhd) */
    GEOM_IMPLICIT_VOLUME_INRIMAGE = 4,  /**< INRIMAGE-4 (.inr, .inr.gz) */
    GEOM_IMPLICIT_VOLUME_NIFTI = 5      /**< NIfTI-1 (.nii, .nii.gz, .hdr + .img) */
} geom_implicit_volume_format;

/**
 * Decompress a zlib (RFC 1950) or gzip (RFC 1952) stream of in_size bytes
 * into out (out_cap bytes), storing the decompressed size in *out_size.
 * Return GEOM_OK, GEOM_ERR_LIMIT when out_cap is too small (the reader then
 * retries with a larger buffer), GEOM_ERR_PARSE for a corrupt stream.
 * libgeom has no compression library: the tools and the Python binding pass
 * one over zlib.
 */
typedef geom_status (*geom_implicit_inflate_fn)(void *user, const void *in, size_t in_size,
                                                void *out, size_t out_cap, size_t *out_size);

/** Options of geom_implicit_volume_read; valid when zero-initialised. */
typedef struct geom_implicit_volume_read_options {
    geom_implicit_volume_format format; /**< 0: detect */
    /* Raw files only (GEOM_IMPLICIT_VOLUME_RAW, or AUTO with dims given): */
    size_t dims[3];              /**< samples per axis, x fastest */
    geom_implicit_sample sample; /**< sample type (0: float32) */
    double spacing[3];           /**< 0 = 1 */
    double origin[3];            /**< default 0 */
    int big_endian;              /**< nonzero: big-endian samples */
    uint64_t skip;               /**< header bytes before the samples */
    /** Decompression for gzip files and NRRD gzip / MetaImage compressed
     *  data; NULL: those are GEOM_ERR_PARSE with a message saying so. */
    geom_implicit_inflate_fn inflate;
    void *inflate_user;
    /** Decompression for NRRD bzip2 data and whole files compressed with
     *  bzip2: a bzip2 stream (concatenated streams continue), with the
     *  contract of geom_implicit_inflate_fn (GEOM_ERR_LIMIT when out_cap is
     *  too small, GEOM_ERR_PARSE for a corrupt or truncated stream). NULL:
     *  bzip2 data is GEOM_ERR_PARSE with a message saying so. The tools pass
     *  one over libbz2 when built with it (Debian libbz2-dev). */
    geom_implicit_inflate_fn bunzip2;
    void *bunzip2_user;
} geom_implicit_volume_read_options;

/** What a volume file said, filled by geom_implicit_volume_read (optional). */
typedef struct geom_implicit_volume_file_info {
    geom_implicit_volume_format format; /**< the format read */
    geom_implicit_sample sample;        /**< the file's sample type */
    int compressed;                     /**< gzip/zlib or bzip2 data was decompressed */
    int flipped[3];                     /**< axis stored in decreasing world order
                                             (a negative direction), reversed on reading */
    int scaled;                         /**< NIfTI scl_slope/scl_inter applied */
    /** Axis whose spacing the header leaves unknown or gives an invalid value
     *  (NRRD "spacings" nan; NIfTI pixdim[1..3] NaN, infinite, zero or
     *  negative) and which was read with spacing 1: the caller should warn.
     *  spacing_note then names the header field, its line or byte offset,
     *  and the value (one line of text). */
    int spacing_defaulted[3];
    char spacing_note[GEOM_DIAG_MESSAGE_MAX];
} geom_implicit_volume_file_info;

/**
 * Read a volume file. Formats (detected by content when options->format is
 * 0; a whole file compressed with gzip is inflated first):
 *  - raw: options->dims samples of options->sample after options->skip
 *    header bytes; the remaining size must be exactly the samples' size;
 *  - NRRD0001..5: all eight sample types (every NRRD spelling), encodings
 *    raw, ascii/text/txt, hex, gzip/gz and bzip2/bz2 (through
 *    options->bunzip2), attached or detached ("data file", relative to the
 *    header) data, "byte skip" (-1 = data ends the file) and "line skip";
 *    placement from "space directions" + "space origin", else "spacings" +
 *    "axis mins". A "spacings" value nan (Teem's "unknown") reads as 1 and
 *    is reported in info->spacing_defaulted; zero or infinite is
 *    GEOM_ERR_PARSE; negative reverses the axis, as a negative direction;
 *  - MetaImage (.mha with ElementDataFile = LOCAL, .mhd naming a data file):
 *    NDims 1..3, ElementNumberOfChannels 1, ElementType MET_UCHAR..
 *    MET_DOUBLE, ElementSpacing/ElementSize, Offset/Origin/Position,
 *    TransformMatrix, ElementByteOrderMSB, HeaderSize, CompressedData; a
 *    spacing that is not a positive finite number is GEOM_ERR_PARSE;
 *  - INRIMAGE-4: XDIM/YDIM/ZDIM, VDIM 1, TYPE (unsigned fixed, signed fixed,
 *    float) with PIXSIZE, CPU (decm/alpha/pc little-endian; sun/sgi big),
 *    VX/VY/VZ spacing (not a positive finite number: GEOM_ERR_PARSE),
 *    XO/YO/ZO (or TX/TY/TZ) origin;
 *  - NIfTI-1 (magic "n+1" single file or "ni1" .hdr naming the .img), either
 *    byte order, datatypes 2, 4, 8, 16, 64, 256, 512, 768, dims beyond the
 *    third of size 1; placement from the sform (sform_code > 0), else the
 *    qform quaternion, else pixdim; scl_slope/scl_inter applied (the volume
 *    is then float64). A pixdim[1..3] the placement uses that is NaN,
 *    infinite, zero or negative (voxel widths are positive in nifti1.h)
 *    reads as 1, as the reference nifti1_io does, and is reported in
 *    info->spacing_defaulted.
 * A whole file compressed with bzip2 is decompressed first too, through
 * options->bunzip2.
 * The placement must be axis-aligned (each grid axis along one world axis,
 * in the same order, within 1e-6 relative); an axis with a negative
 * direction is reversed so that the spacing is positive, which keeps the
 * world positions of the samples. Sizes are checked before allocating; the
 * whole file is read into memory first (peak memory: file + volume).
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL path/out, raw options that
 * geom_implicit_volume_create rejects); GEOM_ERR_IO (cannot open/read: diag
 * names the file and the reason); GEOM_ERR_PARSE (unknown format, malformed
 * header: diag has the file and line, or the byte offset; unsupported type,
 * encoding or orientation; size mismatch; compressed data without inflate
 * or bunzip2; a corrupt or truncated compressed stream, naming the file);
 * GEOM_ERR_LIMIT (sizes overflow); GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_implicit_volume_read(const char *path,
                                               const geom_implicit_volume_read_options *options,
                                               const geom_allocator *alloc,
                                               geom_implicit_volume **out,
                                               geom_implicit_volume_file_info *info,
                                               geom_diag *diag);

/**
 * As geom_implicit_volume_read, from `size` bytes at `data` (never read
 * beyond size); source_name (NULL: "<memory>") names it in diagnostics.
 * Headers naming a separate data file are GEOM_ERR_PARSE.
 */
GEOM_API geom_status geom_implicit_volume_read_memory(const void *data, size_t size,
                                                      const char *source_name,
                                                      const geom_implicit_volume_read_options *options,
                                                      const geom_allocator *alloc,
                                                      geom_implicit_volume **out,
                                                      geom_implicit_volume_file_info *info,
                                                      geom_diag *diag);

/** "u8", "i8", "u16", "i16", "u32", "i32", "f32", "f64"; "?" otherwise. */
GEOM_API const char *geom_implicit_sample_name(geom_implicit_sample s);

/** Parse a sample type name: the names above, and "uint8", "int8", "uint16",
 *  "int16", "uint32", "int32", "float32"/"float", "float64"/"double".
 *  GEOM_ERR_PARSE for anything else, GEOM_ERR_INVALID_ARG for NULL. */
GEOM_API geom_status geom_implicit_sample_parse(const char *name, geom_implicit_sample *out);

/** Bytes per sample of s (1, 2, 4 or 8), 0 for an invalid value. */
GEOM_API size_t geom_implicit_sample_size(geom_implicit_sample s);

/**
 * geom_implicit_volume_eval (grad NULL) or geom_implicit_volume_eval_grad
 * at n points p (3*n doubles) in one call: out receives n values, grad (NULL
 * allowed) 3*n gradient components. A NULL v or p gives NaN values.
 */
GEOM_API void geom_implicit_volume_eval_many(const geom_implicit_volume *v, size_t n,
                                             const double *p, double *out, double *grad);

/** "raw", "nrrd", "metaimage", "inrimage", "nifti"; "auto" for 0. */
GEOM_API const char *geom_implicit_volume_format_name(geom_implicit_volume_format f);

/* ------------------------------------------------------------ root finding */

/** A function of one variable for geom_implicit_bracket_root. */
typedef double (*geom_implicit_root_fn)(void *user, double x);

/**
 * A root of fn in the open interval (a, b), a < b, where fn(a) = fa and
 * fn(b) = fb have opposite strict signs (neither 0, neither NaN), starting
 * from x (e.g. the linear interpolation; moved to the midpoint when not
 * strictly inside): Illinois regula falsi, with a bisection step whenever
 * the bracket has not halved over two steps or a scaled end value is not
 * finite. The one stopping rule of the library's contouring (marching
 * squares, marching cubes' refinement): the bracket ends are adjacent
 * doubles, fn is exactly 0 (that point is returned), fn is NaN, or
 * max_iterations evaluations were made; then the end of the final bracket
 * with the smaller |fn| is returned (at a jump of fn, a point next to the
 * jump), always strictly inside (a, b). *evaluations (may be NULL) is
 * incremented per call of fn. NULL fn or a >= b returns x.
 */
GEOM_API double geom_implicit_bracket_root(geom_implicit_root_fn fn, void *user, double a, double b,
                                           double fa, double fb, double x, int max_iterations,
                                           size_t *evaluations);

/* -------------------------------------------------------- marching squares */

/** Options of geom_implicit_contour; zero-initialised = defaults. */
typedef struct geom_implicit_contour_options {
    double iso;          /**< the isovalue (default 0) */
    double z;            /**< the field is evaluated at (x, y, z) (default 0) */
    int refine;          /**< geom_implicit_refine (default AUTO: refine when
                              field->exact), as geom_iso_options::refine */
    int max_iterations;  /**< root finding iterations per edge; 0 = 100 */
    const geom_allocator *alloc; /**< for the result and temporaries; NULL = libc */
} geom_implicit_contour_options;

/** What geom_implicit_contour achieved. */
typedef struct geom_implicit_contour_report {
    /** error.max_error / mean_error: max and mean over vertices of
     *  |f(v) - iso| / |(df/dx, df/dy)(v)| (a first-order estimate of the
     *  distance to the true isoline of the field in the plane; method
     *  GEOM_ERROR_SAMPLED; the gradient from field->gradient, else central
     *  differences with step 1e-6 of the cell size). Vertices where the
     *  gradient is zero or non-finite are left out (counted in
     *  unmeasured). error.evaluations: every field evaluation made
     *  (samples, root finding, error measure). */
    geom_error_report error;
    size_t unmeasured;    /**< vertices left out of the error measure */
    double seconds;       /**< wall-clock time of the whole call */
    size_t cells;         /**< cells of the grid (nx * ny; those sampled: see
                               *   geom_implicit_contour_estimate_cells) */
    size_t saddles;       /**< ambiguous cells decided by the asymptotic decider */
    size_t skipped_cells; /**< cells with a NaN corner value (NaN is outside;
                               *   the name is kept from when they were skipped) */
    size_t refined;       /**< vertices refined by root finding */
    /** Grid nodes where the field is NaN, and the first of them in scan
     *  order (rows of increasing y, then x): its node index (i, j) and its
     *  point (x, y); zeros when nan_nodes is 0. */
    size_t nan_nodes;
    size_t nan_first[2];
    double nan_point[2];
} geom_implicit_contour_report;

/**
 * Isolines: vertices (2 doubles each) and polylines of vertex indices. A
 * closed polyline lists each vertex once (the closing segment goes from the
 * last back to the first); an open one starts and ends on the grid's
 * border, at a NaN region, at a vertex where more than two segments meet
 * (isolines crossing at a grid node), or where an isoline made of grid
 * nodes with f == iso ends (a zero set of zero width, e.g. the maximum
 * line of (x - c)^2 at iso 0). Polylines are oriented with
 * the inside (f <= iso) on their left, so closed loops around inside regions
 * run counter-clockwise.
 */
typedef struct geom_implicit_isolines {
    size_t n_vertices;
    double *xy;             /**< 2 * n_vertices */
    size_t n_polylines;
    size_t *start;          /**< n_polylines + 1 offsets into indices */
    uint32_t *indices;      /**< start[n_polylines] vertex indices */
    unsigned char *closed;  /**< n_polylines flags: 1 = closed loop */
    geom_implicit_contour_report report;
    geom_allocator alloc;   /**< the allocator used (internal) */
} geom_implicit_isolines;

/**
 * Marching squares on the grid of nx by ny cells covering
 * bounds = {x0, y0, x1, y1} (x0 < x1, y0 < y1): the field is sampled at the
 * (nx + 1) * (ny + 1) nodes x_i = (x0 (nx - i) + x1 i) / nx (likewise y),
 * z = opt->z. A node is inside when f <= iso and outside when f > iso (the
 * library's one inside convention, as geom_iso_extract: values equal to
 * iso are inside, the isoline of iso + epsilon; an isoline through a node
 * passes exactly through it, with one shared vertex and no zero-length or
 * duplicate segment). Each edge with one inside and one outside end holds
 * one vertex, shared by the cells on both sides (keyed by edge id; a
 * crossing at a node with f == iso is keyed by the node); its position is
 * linear interpolation (the edge's midpoint when an end value is
 * infinite), then (refine) safeguarded root finding on the edge (Illinois
 * regula falsi, bisecting whenever the bracket has not halved in two
 * steps) until the bracket ends are adjacent doubles, f is exactly iso, f
 * is NaN or max_iterations is reached; the bracket end with the smaller |f|
 * is kept (at a jump of f, a point next to the jump). A cell whose corners alternate (a saddle)
 * is resolved by the asymptotic decider of Nielson and Hamann (1991): the
 * inside corners are joined when the bilinear interpolant is <= iso at its
 * saddle point (its sign computed from an accurately rounded 2x2
 * determinant; the same decision as geom_iso_extract's on a cell face),
 * which reproduces the topology of the bilinear interpolant of the node
 * values. Infinite values are classified by sign (interpolation then
 * starts at the edge's midpoint) and a NaN value is outside, as +infinity
 * (as geom_iso_extract treats it): a contour closes around the edge of a
 * region where the field is undefined. The saddle decider takes
 * infinities as +-DBL_MAX, as geom_iso_extract's does.
 *
 * Work: when field->bounds is set (expression fields), the grid is cut
 * into blocks of 16 x 16 cells and only the blocks the bounds cannot prove
 * free of the isoline are sampled (see
 * geom_implicit_contour_estimate_cells), so the time grows with the
 * isoline's length rather than with nx * ny; the output is the same as
 * sampling every cell (the dense path, taken without field->bounds), vertex
 * for vertex and in the same order, since a skipped cell makes nothing.
 *
 * Accuracy: with linear interpolation the vertex error is O(h^2) for
 * smooth f; with refinement it is the root of f along the edge to about an
 * ulp of the coordinates (see report->error).
 *
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL field/value/bounds/out,
 * non-finite or empty bounds, nx or ny 0, non-finite iso or z);
 * GEOM_ERR_LIMIT (more than 2^32 - 2 vertices or a grid too large for
 * size_t); GEOM_ERR_NOMEM. On error *out is zeroed (nothing to free).
 */
GEOM_API geom_status geom_implicit_contour(const geom_implicit_field *field, const double bounds[4],
                                  size_t nx, size_t ny,
                                  const geom_implicit_contour_options *opt,
                                  geom_implicit_isolines *out, geom_diag *diag);

/**
 * The number of vertices (and, about as many, segments) geom_implicit_contour
 * would make with the same arguments, estimated before contouring: the field
 * is sampled on a grid of at most 64 x 64 cells over bounds (at z =
 * opt->z), the cells with corners on both sides of opt->iso counted and
 * scaled by the square root of the fine cells per coarse cell (the curves'
 * length). Exact scaling for smooth curves larger than a coarse cell;
 * features thinner than one are missed (an underestimate). Calls
 * field->value at most 65^2 times.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL field, value, bounds or
 * vertices, nx or ny 0, non-finite or empty bounds, non-finite iso or z).
 */
GEOM_API geom_status geom_implicit_contour_estimate(const geom_implicit_field *field,
                                                   const double bounds[4], size_t nx, size_t ny,
                                                   const geom_implicit_contour_options *opt,
                                                   double *vertices);

/**
 * The work geom_implicit_contour would do with the same arguments, before
 * doing it: the number of grid cells it samples. Without field->bounds
 * that is every cell, nx * ny (the dense path). With field->bounds (every
 * expression field has them) the grid is cut into blocks of 16 x 16 cells
 * (larger on grids of more than about 2^36 cells) and the blocks the
 * bounds prove f - iso of one strict sign over are skipped, by recursive
 * halving (a quadtree over the blocks); *cells is then exactly the number
 * of cells in the remaining blocks, the cells geom_implicit_contour
 * samples (each needs at most 4 node values). Costs about 4/3 bounds calls
 * per remaining block times the quadtree depth, plus a bitmap of one bit
 * per block (freed). Lets callers refuse a run that would take too long
 * (geom-contour's --max-cells) even when the output is small.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL field, value, bounds or
 * cells, nx or ny 0, non-finite or empty bounds, non-finite iso or z);
 * GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_implicit_contour_estimate_cells(const geom_implicit_field *field,
                                                         const double bounds[4], size_t nx,
                                                         size_t ny,
                                                         const geom_implicit_contour_options *opt,
                                                         double *cells);

/** Free what geom_implicit_contour allocated and zero *c. NULL or a zeroed
 *  struct is a no-op. */
GEOM_API void geom_implicit_isolines_free(geom_implicit_isolines *c);

/**
 * Append the contour to mesh m as vertices (x, y, z) and polylines (a closed
 * loop repeats its first vertex at the end, as OBJ `l` lines do). Vertex
 * indices are offset by m's vertex count before the call.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL, non-finite z);
 * GEOM_ERR_NOMEM; GEOM_ERR_LIMIT (too many vertices for uint32_t).
 */
GEOM_API geom_status geom_implicit_isolines_to_mesh(const geom_implicit_isolines *c, double z,
                                          geom_mesh *m);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_IMPLICIT_H */
