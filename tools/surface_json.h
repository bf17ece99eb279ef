/*
 * Curves and surfaces from JSON files (tool side: uses cJSON, which the
 * library itself must not depend on). Built into the helper library
 * geom_surface_json by tools/CMakeLists.txt when cJSON is found.
 *
 * Format: one object {"curves": [...], "surfaces": [...]} (either key may
 * be missing). Each entry is an object with
 *   "type":   curves: "bezier", "bspline", "nurbs", "hermite", "catmull_rom",
 *             "kochanek_bartels"; surfaces: "bezier", "bspline", "nurbs";
 *   "name":   optional string;
 *   curves:   "points" (a list of 2D or 3D points, all the same dimension),
 *             "degree" and "knots" (bspline, nurbs; for bezier the degree is
 *             the point count - 1 and may be given to check it), "weights"
 *             (optional, one per point; bezier, bspline, nurbs),
 *             "tangents" (hermite: one per point) and optional "params"
 *             (hermite: strictly increasing, one per point), "alpha"
 *             (catmull_rom: 0 uniform, 0.5 centripetal (default), 1
 *             chordal), "tension", "continuity", "bias" (kochanek_bartels:
 *             a number, or a list with one per point; default 0), "closed"
 *             (catmull_rom, kochanek_bartels: true for a closed loop);
 *   surfaces: "points" as points[i][j] (i along u, j along v, 3D),
 *             "degree_u", "degree_v" (bezier: implied by the shape, checked
 *             when given), "knots_u", "knots_v" (bspline, nurbs), "weights"
 *             as weights[i][j] (optional).
 * Hermite, Catmull-Rom and Kochanek-Bartels splines become their exact
 * piecewise cubic Bezier form as a clamped cubic B-spline with double
 * interior knots (geom_curve_*_to_bezier, geom_curve_piecewise_bezier_knots).
 *
 * Every error names the entry and the key, e.g.
 *   "surfaces[1] (\"torus\"): \"knots_v\": 10 knots, 12 expected (nv + degree_v + 1)"
 * with the file as the diagnostic's source (JSON syntax errors also give
 * the line and column).
 */
#ifndef GEOM_TOOLS_SURFACE_JSON_H
#define GEOM_TOOLS_SURFACE_JSON_H

#include "geom/curve.h"
#include "geom/surface.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One curve: *c borrows the owned arrays. */
typedef struct sj_curve {
    char name[64];
    char type[24];
    geom_nurbs_curve c;
    double *knots, *points, *weights;
} sj_curve;

/** The contents of a file. */
typedef struct sj_file {
    sj_curve *curves;
    size_t ncurves;
    geom_surface_set *surfaces; /**< never NULL after a successful read */
} sj_file;

/** Parse `len` bytes of JSON text (need not be NUL-terminated). source
 *  names it in diagnostics. *out is filled on GEOM_OK (free with sj_free)
 *  and zeroed otherwise. GEOM_ERR_PARSE (syntax, a missing or malformed
 *  key, an invalid curve or surface), GEOM_ERR_NOMEM. */
geom_status sj_read_memory(const char *text, size_t len, const char *source, sj_file *out,
                           geom_diag *diag);

struct cJSON;
/** Parse JSON text (len bytes, no NUL needed) as every tool reads JSON: a
 *  UTF-8 byte-order mark is skipped; a NUL byte, an empty file, a syntax
 *  error (with its line and column) and anything but white space after the
 *  value are GEOM_ERR_PARSE naming `source`. *root (free with cJSON_Delete)
 *  is NULL on error. */
geom_status sj_json_parse(const char *text, size_t len, const char *source, struct cJSON **root,
                          geom_diag *diag);

/** sj_read_memory on the file at path (GEOM_ERR_IO if it cannot be read). */
geom_status sj_read_file(const char *path, sj_file *out, geom_diag *diag);

/** Free what sj_read_* made; safe on a zeroed sj_file. */
void sj_free(sj_file *f);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_TOOLS_SURFACE_JSON_H */
