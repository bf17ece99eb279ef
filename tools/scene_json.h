/*
 * Scene files for ray casting (tool side: cJSON, which libgeom must not
 * depend on). Built into the helper library geom_scene_json by
 * tools/CMakeLists.txt when cJSON is found.
 *
 * A scene is {"objects": [...]}; an object is one of
 *   {"type": "sphere", "center": [x,y,z], "radius": r}
 *   {"type": "plane", "point": [..], "normal": [..]}
 *   {"type": "disk", "center": [..], "normal": [..], "radius": r}
 *   {"type": "box", "min": [..], "max": [..]}
 *   {"type": "obox", "center": [..], "axes": [[..],[..],[..]], "half": [..]}
 *   {"type": "torus", "major": R, "minor": r}            (axis z, centre 0)
 *   {"type": "quadric", "coefficients": [a,b,c,d,e,f,g,h,i,j]}
 *        a x^2 + b y^2 + c z^2 + 2d xy + 2e yz + 2f xz + 2g x + 2h y + 2i z + j = 0,
 *        optional "clip": [x0,y0,z0,x1,y1,z1] and "capped": true|false
 *   {"type": "triangle", "vertices": [[..],[..],[..]]}
 *   {"type": "polygon", "vertices": [[..], ...]}
 *   {"type": "mesh", "file": "x.obj"}                   (OBJ, OFF, PLY, STL)
 *   {"type": "surface", "file": "s.json"}               (curve/surface JSON: every surface)
 *   {"type": "bezier"|"bspline"|"nurbs", ...}           (inline surface, surface JSON keys)
 *   {"type": "subdivision", "file": "x.obj", "scheme": "catmull-clark"|"loop", "levels": n}
 *   {"type": "implicit", "expr": "...", "bounds": [x0,y0,z0,x1,y1,z1], "lipschitz": L}
 *   {"type": "volume", "file": "v.nrrd", "iso": v, "inside": "below"|"above"}
 *        (every format geom-iso --volume reads; raw: "dims": [x,y,z],
 *        "sample": "u16", optional "skip", "spacing", "origin",
 *        "big_endian"; "inside": f <= iso or f >= iso is inside, absent:
 *        detected from the boundary samples as geom-iso --volume does)
 *   {"type": "csg", "op": "union"|"intersection"|"difference", "children": [obj, obj, ...]}
 *        (more than two children fold from the left)
 *   {"type": "instance", "of": "name"}
 * Any object may carry "name", and "transform": {"translate": [..],
 * "rotate": [deg, ax, ay, az], "scale": [..] or s} (applied scale, then
 * rotate, then translate; rotate is right-handed about the normalised axis)
 * or "matrix": [16 numbers, column-major]. An instance applies its
 * transform after the named object's own; a named object is part of the
 * scene itself; instances may refer to names defined anywhere in the file.
 * Relative file paths are relative to the scene file. Unknown keys are
 * ignored (other layers, e.g. materials, share the file).
 *
 * Every error names the object and the key, e.g.
 *   "objects[2] (\"ball\"): \"radius\": expected a number > 0"
 * with the scene file as the diagnostic's source (JSON syntax errors give
 * the line and column).
 */
#ifndef GEOM_TOOLS_SCENE_JSON_H
#define GEOM_TOOLS_SCENE_JSON_H

#include "geom/ray.h"

#ifdef __cplusplus
extern "C" {
#endif

struct cJSON;

/** What a parsed scene owns: the library scene (not yet built) and the
 *  expressions and volumes it borrows. Free with scene_json_free. */
typedef struct scene_json_objects {
    geom_ray_scene *scene;
    size_t nobjects;          /**< top-level objects (= entries of "objects") */
    void **owned;             /**< expressions and volumes the scene borrows */
    int *owned_kind;          /**< 0 expression, 1 volume */
    size_t nowned, owned_cap;
} scene_json_objects;

/**
 * Parse the "objects" array `objects` (a cJSON array) into out->scene, the
 * top-level objects in array order. base_dir: directory for relative paths
 * ("" or NULL: current directory); source: the file name for diagnostics.
 * tool_name: prefix of the repair messages mesh reading prints (may be
 * NULL). *out is zeroed first; on error everything is freed.
 * Statuses: GEOM_ERR_PARSE (a missing or malformed key, unknown type or
 * name), GEOM_ERR_IO (a referenced file), the library's, GEOM_ERR_NOMEM.
 */
geom_status scene_json_parse_objects(const struct cJSON *objects, const char *base_dir,
                                     const char *source, const char *tool_name,
                                     scene_json_objects *out, geom_diag *diag);

/** Read a scene file (path) with scene_json_parse_objects on its "objects". */
geom_status scene_json_read_file(const char *path, const char *tool_name, scene_json_objects *out,
                                 geom_diag *diag);

/** Parse JSON text (len bytes) as scene_json_read_file does (base_dir for
 *  relative paths, source for diagnostics). */
geom_status scene_json_read_memory(const char *text, size_t len, const char *base_dir,
                                   const char *source, const char *tool_name,
                                   scene_json_objects *out, geom_diag *diag);

/** Free what the functions above made; safe on a zeroed struct. */
void scene_json_free(scene_json_objects *o);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_TOOLS_SCENE_JSON_H */
