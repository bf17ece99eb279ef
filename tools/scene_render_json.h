/*
 * The rendering part of a scene JSON file (tool side, through cJSON): the
 * camera, the lights, the materials and the background. The "objects" are
 * read by the ray module's scene parser (scene_json.h); an object refers to
 * a material by name with "material": "name".
 *
 *   "camera": {"eye": [x,y,z], "center": [..], "up": [..] (default 0,1,0),
 *              "fovy": degrees (default 45) | "projection": "orthographic"
 *              with "ortho_height": world units (default 2),
 *              "width", "height": pixels (default 320 x 240),
 *              "samples": N (default 1), "sampling": "regular" | "jittered",
 *              "adaptive": {"max_samples": N, "tolerance": T}}
 *   "lights": [{"type": "point", "position": [..], "color": c},
 *              {"type": "directional", "direction": [..], "color": c},
 *              {"type": "ambient", "color": c}]      (c: number or RGB, default 1)
 *   "materials": {"name": {"ka", "kd", "ks": number or RGB, "ns": n,
 *              "specular": "blinn" | "phong", "reflect", "transmit", "ior",
 *              "texture": "file.png", "wrap": "repeat" | "clamp",
 *              "bump": "h.png", "bump_scale", "normal_map": "n.png",
 *              "displace": "h.png", "displace_scale",
 *              "shading": "flat" | "gouraud" | "phong",
 *              "style": "cool-to-warm", "line_width", "crease_degrees"}}
 *   "background": c
 * Unset material keys take geom_scene_material_default()'s values. Image paths are
 * relative to the scene file; colour textures are decoded from sRGB, height
 * and normal maps are read as stored. Errors name the key
 * ("materials.glass.ior: expected a number").
 */
#ifndef GEOM_TOOLS_SCENE_RENDER_JSON_H
#define GEOM_TOOLS_SCENE_RENDER_JSON_H

#include <cjson/cJSON.h>

#include "geom/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct srj_scene {
    geom_camera camera;
    int has_camera;
    geom_vec3 background;
    geom_light *lights;
    size_t n_lights;
    geom_material *materials; /**< materials[0] is the default material "" */
    char **material_names;
    size_t n_materials;
    geom_texture **textures;  /**< owned, referenced by the materials */
    char **texture_paths;
    size_t n_textures;
} srj_scene;

/** Read camera, lights, materials and background from the parsed root
 *  object; `scene_path` locates relative image paths and names the source in
 *  diagnostics. On error *out is freed and zeroed. */
geom_status srj_parse(const cJSON *root, const char *scene_path, srj_scene *out, geom_diag *diag);

/** The index of material `name` (0, the default, for NULL or ""), or
 *  UINT32_MAX when there is no such material. */
uint32_t srj_material_index(const srj_scene *s, const char *name);

/** Free everything; safe on a zeroed srj_scene. */
void srj_free(srj_scene *s);

/** A whole scene file: rendering part, objects (parsed by the ray module's
 *  scene_json parser) and their shapes, names and materials. */
typedef struct srj_file {
    srj_scene render;
    void *objects_json;             /**< scene_json_objects * (owned) */
    geom_scene_shapes *shapes;
    geom_scene_object *objects;     /**< n_objects: shape + material */
    char **names;                   /**< n_objects: "name" or "objects[i]" */
    size_t n_objects;
} srj_file;

/** Read and parse `path` completely. Errors name the file, the line and
 *  column for JSON syntax, the object and key otherwise. */
geom_status srj_load(const char *path, const char *tool_name, srj_file *out, geom_diag *diag);
void srj_file_free(srj_file *f);

#ifdef __cplusplus
}
#endif

#endif
