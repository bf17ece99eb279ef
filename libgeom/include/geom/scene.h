/*
 * libgeom scene: cameras, lights, materials, textures, local shading and two
 * ways of making a picture of geometry: a z-buffer rasterizer over triangle
 * meshes (the preview path) and, with the ray module, Whitted ray tracing.
 *
 * Conventions:
 *  - images are row-major with the top row first; pixel (i, j) covers
 *    [i, i+1) x [j, j+1) in pixel coordinates, its centre is (i+0.5, j+0.5);
 *    i grows to the right, j downwards;
 *  - colours are linear RGB doubles (no gamma; writers convert);
 *  - texture coordinates: (0,0) is the bottom-left corner of the image and
 *    (1,1) the top-right (the OBJ/OpenGL convention), texel (x, y) has its
 *    centre at ((x+0.5)/w, 1-(y+0.5)/h);
 *  - the camera is gluLookAt's: it looks from eye to center, up projected on
 *    the screen's vertical; perspective as gluPerspective, orthographic as
 *    glOrtho with a view `height` in world units; the aspect ratio is
 *    width/height in pixels; both methods see only what is in front of the
 *    eye (orthographic rays start on the plane through the eye);
 *  - nothing prints, nothing keeps global state; every function is
 *    reentrant.
 */
#ifndef GEOM_SCENE_H
#define GEOM_SCENE_H

#include "geom/core.h"
#include "geom/implicit.h"
#include "geom/mesh.h"
#include "geom/ray.h"
#include "geom/surface.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ images */

/** A w x h image of `channels` doubles per pixel, row-major, top row first. */
typedef struct geom_image {
    uint32_t width, height, channels;
    double *data; /**< width*height*channels doubles */
} geom_image;

/** Allocate img->data (zero-filled) for w x h x channels (all >= 1).
 *  GEOM_ERR_INVALID_ARG for a zero size or NULL, GEOM_ERR_LIMIT when the size
 *  overflows, GEOM_ERR_NOMEM. */
GEOM_API geom_status geom_scene_image_init(geom_image *img, uint32_t width, uint32_t height,
                                     uint32_t channels, const geom_allocator *alloc);
/** Free what geom_scene_image_init allocated (with the same allocator) and zero the
 *  struct. NULL or an empty image is a no-op. */
GEOM_API void geom_scene_image_free(geom_image *img, const geom_allocator *alloc);

/* ---------------------------------------------------------------- textures */

typedef enum geom_wrap {
    GEOM_WRAP_REPEAT = 0, /**< default: coordinates taken modulo 1 */
    GEOM_WRAP_CLAMP = 1   /**< clamped to the edge texels */
} geom_wrap;

/** A texture: an image with its MIP pyramid (Williams 1983), immutable once
 *  made, so one texture may be sampled from any number of threads. */
typedef struct geom_texture geom_texture;

/**
 * Make a texture from `img` (1 to 4 channels, values copied) with its MIP
 * pyramid: each level halves each size (rounding down, at least 1) by a box
 * filter over the 2x2 (or 2x1, or for odd sizes the 3-tap) footprint, down to
 * 1x1. GEOM_ERR_INVALID_ARG for NULL/empty input or non-finite texels,
 * GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_scene_texture_create(const geom_image *img, geom_wrap wrap,
                                         const geom_allocator *alloc, geom_texture **out);
/** NULL is a no-op. */
GEOM_API void geom_scene_texture_destroy(geom_texture *t);
/** Channels per texel (1..4) and the size of level 0. */
GEOM_API uint32_t geom_scene_texture_channels(const geom_texture *t);
GEOM_API void geom_scene_texture_size(const geom_texture *t, uint32_t *width, uint32_t *height);
/** Number of MIP levels (1 for a 1x1 texture). */
GEOM_API uint32_t geom_scene_texture_levels(const geom_texture *t);

/**
 * Sample at (u, v) into out (channels doubles). footprint is the size in UV
 * units of the screen pixel's footprint (the larger of |d(u,v)/dx| and
 * |d(u,v)/dy|); 0 or less means level 0 only, i.e. plain bilinear
 * interpolation. Otherwise trilinear: lod = log2(footprint * max(w, h)),
 * bilinear in the two nearest levels, linearly blended. Non-finite (u, v)
 * give texel (0, 0) of level 0. Exact for bilinear data on level 0.
 */
GEOM_API void geom_scene_texture_sample(const geom_texture *t, double u, double v, double footprint,
                                  double *out);

/**
 * Partial derivatives of channel 0 of level 0's bilinear interpolant with
 * respect to u and v at (u, v) (the height-map slopes for bump mapping), in
 * channel units per UV unit.
 */
GEOM_API void geom_scene_texture_gradient(const geom_texture *t, double u, double v, double *dh_du,
                                    double *dh_dv);

/**
 * geom_scene_texture_sample and geom_scene_texture_gradient over n points in
 * one call (bitwise their results): uv holds 2*n doubles (u, v per point);
 * footprint[i * footprint_stride] is point i's footprint (stride 1 for one
 * per point, 0 for one shared by all; footprint NULL means 0 for every
 * point). out (channels*n doubles, point by point) receives the samples and
 * grad (2*n doubles: dh/du, dh/dv per point) the gradients; either may be
 * NULL to skip that part. GEOM_ERR_INVALID_ARG for NULL t or uv with n > 0
 * (nothing written); GEOM_OK otherwise.
 */
GEOM_API geom_status geom_scene_texture_sample_many(const geom_texture *t, size_t n,
                                                    const double *uv, const double *footprint,
                                                    size_t footprint_stride, double *out,
                                                    double *grad);

/* ------------------------------------------------------------------ camera */

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

/** The effective (defaulted) values of a camera. */
GEOM_API geom_camera geom_scene_camera_resolved(const geom_camera *cam);

/**
 * The primary ray through the point (x, y) in pixel coordinates: origin at
 * the eye (perspective) or on the view plane through the eye (orthographic),
 * unit direction, tmin 0, tmax +inf. GEOM_ERR_DEGENERATE for eye == center or
 * up parallel to the view direction, GEOM_ERR_DOMAIN for a field of view
 * outside (0, 180) degrees or a non-positive orthographic height.
 */
GEOM_API geom_status geom_scene_camera_ray(const geom_camera *cam, double x, double y, geom_ray *out);

/**
 * View and projection matrices (OpenGL convention) for the rasterizer and
 * shadow maps, with the given near and far distances (0 < near < far).
 * Either output may be NULL. Statuses as geom_scene_camera_ray.
 */
GEOM_API geom_status geom_scene_camera_matrices(const geom_camera *cam, double near_z, double far_z,
                                          geom_mat4 *view, geom_mat4 *proj);

/**
 * Project world point p to pixel coordinates (x, y) and view depth (distance
 * along the view direction, positive in front). GEOM_ERR_DOMAIN when p is not
 * in front of a perspective camera. out: 3 doubles.
 */
GEOM_API geom_status geom_scene_camera_project(const geom_camera *cam, geom_vec3 p, double out[3]);

/**
 * World-space size of one pixel at view depth `depth` (the pixel's footprint
 * on a plane facing the camera): 2*depth*tan(fovy/2)/height for perspective,
 * ortho_height/height for orthographic. Used to turn a pixel error into a
 * chordal tolerance.
 */
GEOM_API double geom_scene_camera_pixel_size(const geom_camera *cam, double depth);

/**
 * Chordal tolerance (world units) that keeps the projected error of an
 * object with world bounding box `box` below `pixel_error` pixels where it
 * can be seen: pixel_error * geom_scene_camera_pixel_size at the box's nearest
 * view depth (not closer than 1e-3 of the box's diagonal). *visible (may be
 * NULL) is 1 when the box meets the view frustum; a box outside it gets 8
 * times the tolerance (it can only cast shadows). 0 for an empty box, a
 * non-positive pixel_error or a degenerate camera.
 */
GEOM_API double geom_scene_pixel_tolerance(const geom_camera *cam, geom_aabb box,
                                           double pixel_error, int *visible);

/* ------------------------------------------------------------------ lights */

typedef enum geom_light_kind {
    GEOM_LIGHT_POINT = 0,       /**< at `position`, no fall-off */
    GEOM_LIGHT_DIRECTIONAL = 1, /**< light travelling along `direction` */
    GEOM_LIGHT_AMBIENT = 2      /**< `color` times the material's ka, unshadowed */
} geom_light_kind;

typedef struct geom_light {
    geom_light_kind kind;
    geom_vec3 position;
    geom_vec3 direction;
    geom_vec3 color; /**< linear RGB intensity */
} geom_light;

/* --------------------------------------------------------------- materials */

typedef enum geom_shading {
    GEOM_SHADING_PHONG = 0,   /**< normal interpolated, lit per pixel (default) */
    GEOM_SHADING_GOURAUD = 1, /**< lit at the vertices, colour interpolated */
    GEOM_SHADING_FLAT = 2     /**< one geometric normal per triangle */
} geom_shading;

typedef enum geom_specular {
    GEOM_SPECULAR_BLINN = 0, /**< ks (n.h)^ns, h the half vector (Blinn 1977); default */
    GEOM_SPECULAR_PHONG = 1  /**< ks (r.v)^ns, r the mirrored light (Phong 1975) */
} geom_specular;

typedef enum geom_style {
    GEOM_STYLE_STANDARD = 0,
    GEOM_STYLE_COOL_TO_WARM = 1 /**< Gooch et al. 1998, with silhouette and crease lines */
} geom_style;

/**
 * A material. The zero material is black and matte; geom_scene_material_default()
 * gives the JSON defaults (kd 0.8, ka 0.1, ks 0, ns 32, ior 1).
 */
typedef struct geom_material {
    geom_vec3 ka, kd, ks;   /**< ambient, diffuse, specular reflectances */
    double ns;              /**< specular exponent */
    geom_specular specular;
    double reflect;         /**< mirror reflection weight in [0, 1] */
    double transmit;        /**< refraction weight in [0, 1] */
    double ior;             /**< index of refraction inside; 0 = 1 */
    const geom_texture *texture;    /**< multiplies kd and ka (RGB or grey), by the UVs */
    const geom_texture *bump;       /**< height map (channel 0), Blinn 1978 */
    double bump_scale;              /**< heights scaled by this; 0 = 1 */
    const geom_texture *normal_map; /**< tangent-space normals, RGB in [0,1] -> [-1,1] */
    const geom_texture *displace;   /**< height map moved along the normal (tessellation) */
    double displace_scale;          /**< 0 = 1 */
    geom_shading shading;
    geom_style style;
    /** COOL_TO_WARM: k_cool = (0,0,b) + alpha*kd, k_warm = (y,y,0) + beta*kd;
     *  0 means the paper's b = 0.4, y = 0.4, alpha = 0.2, beta = 0.6. */
    double gooch_b, gooch_y, gooch_alpha, gooch_beta;
    double line_width;       /**< COOL_TO_WARM lines in pixels; 0 = 1.5 */
    double crease_degrees;   /**< COOL_TO_WARM crease lines; 0 = 30 */
} geom_material;

/** kd = (0.8,0.8,0.8), ka = (0.1,0.1,0.1), ks = 0, ns = 32, ior = 1, the rest 0. */
GEOM_API geom_material geom_scene_material_default(void);

/** What the material needs from the geometry (OR of these flags): UVs for a
 *  texture, bump, normal or displacement map; tangents for a normal map or a
 *  bump map; refraction rays for transmit > 0; reflection rays for reflect > 0. */
enum {
    GEOM_NEEDS_UV = 1,
    GEOM_NEEDS_TANGENT = 2,
    GEOM_NEEDS_NORMAL = 4,
    GEOM_NEEDS_REFLECTION = 8,
    GEOM_NEEDS_REFRACTION = 16
};
GEOM_API unsigned geom_scene_material_needs(const geom_material *m);

/* ---------------------------------------------------------------- shading */

/** One shading point, in world space. */
typedef struct geom_shade_point {
    geom_vec3 p;          /**< position */
    geom_vec3 n;          /**< unit shading normal (facing the viewer is not required) */
    geom_vec3 ng;         /**< unit geometric normal, 0 = n */
    geom_vec3 v;          /**< unit direction from p toward the viewer */
    double uv[2];
    int has_uv;
    geom_vec3 tangent;    /**< unit tangent (dP/du direction), for normal/bump maps */
    double tangent_sign;  /**< bitangent = sign * n x tangent; 0 = 1 */
    int has_tangent;
    double footprint;     /**< UV footprint of the pixel for MIP-mapping (0 = level 0) */
} geom_shade_point;

/**
 * The shading normal after bump mapping (Blinn 1978: N' = N + h_u (N x P_v)
 * - h_v (N x P_u), with the unit tangent T = sp->tangent standing for P_u,
 * the bitangent B = sign * N x T for P_v, and the height map's gradient
 * (geom_scene_texture_gradient, channel 0) times bump_scale) or a tangent-space
 * normal map (RGB in [0,1] mapped to [-1,1]: n = T*x + B*y + N*z); otherwise
 * sp->n. Needs
 * sp->has_uv and, for both maps, sp->has_tangent; without them sp->n is
 * returned unchanged. Flipped to face the viewer (n.v >= 0).
 */
GEOM_API geom_vec3 geom_scene_shade_normal(const geom_material *m, const geom_shade_point *sp);

/**
 * Local illumination at sp with normal n (from geom_scene_shade_normal): the sum
 * over lights of ambient ka*C, diffuse kd*C*max(0, n.l) and specular
 * ks*C*(n.h)^ns or (r.v)^ns (zero when n.l <= 0), each light's term scaled by
 * visibility[i] in [0,1] (NULL: all visible; ambient lights ignore it). kd
 * and ka are multiplied by the texture colour when there is one and sp has
 * UVs. The normal is flipped toward the viewer first (two-sided lighting).
 * COOL_TO_WARM materials instead give (1+n.l)/2 k_cool + (1-(1+n.l)/2) k_warm
 * for the first non-ambient light plus the specular term (Gooch et al. 1998,
 * eq. 2). out: RGB.
 */
GEOM_API void geom_scene_shade(const geom_material *m, const geom_light *lights, size_t n_lights,
                         const double *visibility, const geom_shade_point *sp, geom_vec3 n,
                         geom_vec3 *out);

/* -------------------------------------------------------------- rasterizer */

/** One mesh to draw: triangles or polygons (fan-triangulated), positions in
 *  object space. Channels used when present: "normal" (VERTEX or CORNER, 3),
 *  "uv" (CORNER or VERTEX, 2), "tangent" (CORNER, 4). */
typedef struct geom_scene_draw {
    const geom_mesh *mesh;
    const geom_mat4 *transform; /**< object to world; NULL = identity */
    uint32_t material;          /**< index into the materials array */
    uint32_t object_id;         /**< written to the "object" AOV */
} geom_scene_draw;

typedef enum geom_aov {
    GEOM_AOV_COLOR = 0,  /**< linear RGB */
    GEOM_AOV_DEPTH = 1,  /**< distance along the view direction (1 channel, +inf on background) */
    GEOM_AOV_NORMAL = 2, /**< world shading normal (3 channels, 0 on background) */
    GEOM_AOV_OBJECT = 3  /**< object id (1 channel, -1 on background) */
} geom_aov;

typedef struct geom_raster_options {
    geom_aov aov;
    geom_vec3 background;      /**< background colour; default black */
    int shadows;               /**< nonzero: shadow maps for point and directional lights */
    uint32_t shadow_map_size;  /**< per face; 0 = 1024 */
    double near_z, far_z;      /**< 0 = from the scene's bounding box */
    const geom_allocator *alloc;
} geom_raster_options;

typedef struct geom_raster_report {
    size_t triangles_in;       /**< triangles submitted */
    size_t triangles_clipped;  /**< triangles after frustum clipping */
    size_t fragments;          /**< samples that passed the depth test when drawn */
    size_t shadow_maps;        /**< shadow-map faces rendered */
    uint32_t samples_per_pixel;
    double seconds_clip, seconds_raster, seconds_shade, seconds_shadow;
} geom_raster_report;

/**
 * Z-buffer rasterization (Catmull 1974) of the draws: each mesh clipped to
 * the view frustum with geom_mesh_clip_frustum, triangles scan-converted with
 * edge functions at the sample positions (top-left fill rule, so a shared
 * edge covers each sample once), attributes interpolated perspective-correctly
 * with geom_bary_perspective, then shaded once per visible sample with
 * geom_scene_shade (flat, Gouraud or Phong as each material says). The
 * projected vertices are snapped to a grid of 1/256 of the sample spacing
 * before the edge functions (so coverage and the fill rule are exact: a
 * vertex moves by at most 1/512 of a sample spacing on each axis, and the
 * barycentric weights, hence the interpolated attributes and depth, are
 * those of the snapped triangle). Textures are
 * MIP-mapped with the pixel's UV footprint. With opt->shadows, each point
 * light gets a cube shadow map and each directional light an orthographic one
 * over the scene's bounding box (Williams 1978), depth-biased by the map's
 * texel size. Samples: a regular k x k grid per pixel at the centres of its
 * k x k sub-pixels, k = ceil(sqrt(cam->samples)) clamped to 1..16 (always
 * regular: cam->sampling is not used here). Colour and normal outputs are
 * box filtered: the plain mean of the pixel's k*k samples (background
 * samples included; the mean normal is not renormalised). Depth and object
 * id are not filtered: each pixel takes the one sample at sub-pixel (k/2,
 * k/2) (integer division: the pixel centre for odd k, the sample below and
 * right of the centre for even k). COOL_TO_WARM materials get silhouette
 * and crease lines where the visibility buffer changes object or the
 * normal turns by more than the crease angle between neighbouring samples.
 * out receives a fresh image (3 channels for colour, 1 for depth/object, 3 for
 * normal) that the caller frees with geom_scene_image_free(out, opt->alloc).
 * Returns GEOM_ERR_INVALID_ARG for NULL arguments, a material index out of
 * range or non-finite positions, camera statuses as geom_scene_camera_ray,
 * GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_scene_raster(const geom_camera *cam, const geom_light *lights,
                                       size_t n_lights, const geom_material *materials,
                                       size_t n_materials, const geom_scene_draw *draws,
                                       size_t n_draws, const geom_raster_options *opt,
                                       geom_image *out, geom_raster_report *report);

/* ----------------------------------------------------------- tessellation */

typedef enum geom_shape_kind {
    GEOM_SHAPE_SPHERE = 1,   /**< p = centre, radius */
    GEOM_SHAPE_BOX,          /**< min, max */
    GEOM_SHAPE_PLANE,        /**< p = point, n = normal (unbounded: request->extent) */
    GEOM_SHAPE_DISK,         /**< p = centre, n = normal, radius */
    GEOM_SHAPE_TORUS,        /**< about z at the origin: major, minor */
    GEOM_SHAPE_QUADRIC,      /**< q[10] as the ray module, clip (6 doubles or NULL), capped */
    GEOM_SHAPE_POLYGON,      /**< vertices (3*n_vertices doubles), a triangle when n = 3 */
    GEOM_SHAPE_MESH,         /**< mesh */
    GEOM_SHAPE_SURFACE,      /**< surfaces[n_surfaces] (B-spline/NURBS) */
    GEOM_SHAPE_SUBDIV,       /**< mesh refined toward the limit, scheme (geom_subdiv_scheme) */
    GEOM_SHAPE_IMPLICIT,     /**< expr, inside < 0, within bounds */
    GEOM_SHAPE_VOLUME,       /**< volume, iso, inside */
    GEOM_SHAPE_CSG,          /**< csg_op (1 union, 2 intersection, 3 difference a - b) of a, b */
    GEOM_SHAPE_GROUP         /**< members[n_members], answered as one object */
} geom_shape_kind;

/**
 * A shape to tessellate: the parameters of one scene object in its own
 * frame (what the ray module traces directly), with an optional transform
 * to its parent's frame. Only the fields of its kind are read. Everything
 * is borrowed.
 */
typedef struct geom_shape {
    geom_shape_kind kind;
    const char *name;              /**< for diagnostics; may be NULL */
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
    const geom_mat4 *transform;    /**< local to parent; NULL = identity */
    int inside;                    /**< volume: which side of iso is inside, as
                                        geom_ray_volume_options::inside (0: f < iso,
                                        the default; 1: f > iso, e.g. CT) */
} geom_shape;

/** The shapes of a ray-module scene (the one representation the scene JSON
 *  parser builds), owned by this object. */
typedef struct geom_scene_shapes geom_scene_shapes;

/**
 * The top-level objects of rs (geom_ray_scene_set_objects' list, else every
 * node that is no CSG or group member) as shapes: analytic nodes with their
 * parameters, oriented boxes as boxes under a transform, meshes and
 * subdivision surfaces as the triangle meshes the ray module holds (the
 * subdivision's refined limit mesh, with its limit normals), surfaces,
 * implicit surfaces, volumes, CSG and groups as trees, instances as a copy
 * of their target under the composed transform. rs need not be built and
 * must outlive the result (surfaces, expressions and volumes are borrowed).
 * GEOM_ERR_INVALID_ARG (NULL), GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_scene_shapes_from_ray(const geom_ray_scene *rs, geom_scene_shapes **out,
                                                geom_diag *diag);
GEOM_API size_t geom_scene_shapes_count(const geom_scene_shapes *s);
/** Shape i (< count), or NULL. */
GEOM_API const geom_shape *geom_scene_shapes_get(const geom_scene_shapes *s, size_t i);
/** The ray-module kind name of top-level object i ("sphere", "mesh", ...). */
GEOM_API const char *geom_scene_shapes_kind_name(const geom_scene_shapes *s, size_t i);
/** NULL is a no-op. */
GEOM_API void geom_scene_shapes_destroy(geom_scene_shapes *s);

typedef struct geom_tess_request {
    double tol;          /**< chordal tolerance in the shape's frame (> 0) */
    unsigned attributes; /**< OR of GEOM_NEEDS_NORMAL, GEOM_NEEDS_UV, GEOM_NEEDS_TANGENT */
    geom_aabb extent;    /**< region that unbounded shapes (planes, unclipped quadrics,
                              CSG with them) are cut to, in the shape's frame;
                              empty or a single point (the zero box) = none */
} geom_tess_request;

typedef struct geom_tess_info {
    geom_error_report error; /**< achieved chordal error (how: see method) */
    size_t triangles;
    double seconds;
    const char *method;      /**< "exact", "nurbs", "iso", "subdiv", "polygon", "mesh" */
} geom_tess_info;

/**
 * Tessellate s into `out` (replaced) in s's own frame (s->transform is NOT
 * applied: pass it to the draw, or use geom_scene_mesh_transform), with the
 * channels the request asks for: CORNER "normal" (3), "uv" (2), "tangent"
 * (4) where the method can make them (spheres, tori and surfaces through
 * the surface module's exact NURBS and geom_surface_tessellate, adaptive to
 * tol: "nurbs"; boxes, disks, polygons and planes exactly: "exact" /
 * "polygon"; meshes as they are, with their "uv", "normal" and "tangent"
 * VERTEX and CORNER channels: "mesh"; subdivision surfaces refined until
 * the distance of the refined control points to the limit (measured at
 * every vertex) is below tol, then moved onto the limit: "subdiv";
 * implicit surfaces, volumes, quadrics and CSG by marching cubes of their
 * implicit form (min/max of the children's: sphere, box, torus, plane,
 * quadric, implicit, volume, CSG), doubling the resolution (at most twice) until the
 * iso module's sampled error is below tol or 256 cells per axis: "iso";
 * sharp CSG edges may then stay above tol, which the report shows).
 * A CSG child without an implicit form (mesh, surface, subdivision,
 * polygon, disk) gives GEOM_ERR_INVALID_ARG with its name in diag.
 * Statuses: GEOM_ERR_INVALID_ARG (bad parameters, tol <= 0, an unbounded
 * shape with an empty extent), GEOM_ERR_NOMEM, and those of the modules
 * used.
 */
GEOM_API geom_status geom_scene_tessellate(const geom_shape *s, const geom_tess_request *rq,
                                           geom_mesh *out, geom_tess_info *info, geom_diag *diag);

/**
 * The number of triangles geom_scene_tessellate(s, rq, ...) would make,
 * estimated before the work (for callers that refuse an output too large):
 * spheres, tori and surfaces: geom_surface_tess_estimate at rq->tol (not a
 * bound: typically within a factor 2); boxes 12, planes 2, polygons n - 2,
 * disks their sides - 2 (exact); meshes their faces' valence - 2 summed
 * (exact); subdivision surfaces: the control points' limit distance at
 * level 1 (geom_subdiv_mesh, one level: the tessellation's first step)
 * taken to shrink 4 times a
 * level, which gives the level geom_scene_tessellate stops at (1..7), and
 * the faces of that level (Catmull-Clark: 2 triangles per quad, one quad
 * per level-0 corner times 4^(level-1); other schemes 4^level triangles
 * per triangle); quadrics, implicit surfaces, volumes and CSG: an upper
 * bound: geom_scene_tessellate's marching-cubes passes are done here as it
 * does them (without normals) while their grid has at most 2^22 cells
 * (161^3), so the count is exact when the pass that reaches tol (or the
 * last) is among them; otherwise the last pass is assumed (the error of
 * a larger pass is not known without doing it) and its count is the
 * largest tried grid's scaled by the ratio of cells to the 2/3 (the
 * surface's area), plus 10 % (measured 1.00 to 1.10 times the triangles
 * made on spheres, tori, a gyroid, a capped cylinder, a CSG difference and
 * a volume from tol 1e-1 to 1e-3 of the size; up to 4 times when the
 * assumed last pass is not needed). The cost: at most that of the passes
 * tried, i.e. up to geom_scene_tessellate's own for such shapes (a guard
 * that only needs to know the output is under a limit:
 * geom_scene_export_estimate with max_triangles, a cheap bound). Groups:
 * the sum over their members. s->transform is not applied
 * (rq->tol is in s's frame, as for geom_scene_tessellate).
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (NULL pointers, tol <= 0, a
 * shape without its data, an unbounded implicit shape with an empty
 * extent, a CSG child without an implicit form); GEOM_ERR_NOMEM; and
 * geom_subdiv_mesh's.
 */
GEOM_API geom_status geom_scene_tessellate_estimate(const geom_shape *s, const geom_tess_request *rq,
                                                    double *triangles);

/**
 * Displacement mapping: move every vertex of m along its angle-weighted
 * vertex normal by scale (0 = 1) times channel 0 of `height` at the vertex's
 * UV ("uv" VERTEX channel, else its first corner's: vertices on a UV seam
 * take one side's value), then replace the normals by the displaced
 * surface's vertex normals. The displacement is sampled at the vertices
 * only: tessellate finely enough for the map's detail. GEOM_ERR_INVALID_ARG
 * without UVs, GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_scene_displace(geom_mesh *m, const geom_texture *height, double scale);

/** Apply the affine transform M to m in place: positions, "normal" channels
 *  (inverse transpose, renormalised), "tangent" xyz (renormalised).
 *  GEOM_ERR_DEGENERATE for a singular M. */
GEOM_API geom_status geom_scene_mesh_transform(geom_mesh *m, geom_mat4 M);

/* ----------------------------------------------------------- ray tracing */

typedef struct geom_trace_options {
    geom_aov aov;
    geom_vec3 background;  /**< colour of rays that leave the scene; default black */
    uint32_t max_depth;    /**< reflection/refraction bounces; 0 = 8 */
    double min_weight;     /**< a secondary ray whose weight falls below this is not
                                traced; 0 = 1/256 */
    int no_shadows;        /**< nonzero: no shadow rays (every light visible) */
    const geom_allocator *alloc;
    /** Called (when not NULL) after each image row with the fraction of the
     *  rows done, in [0, 1]; for progress displays. */
    void (*progress)(void *user, double fraction);
    void *progress_user;
} geom_trace_options;

typedef struct geom_trace_report {
    size_t primary_rays;     /**< camera samples traced */
    size_t shadow_rays;
    size_t reflection_rays;
    size_t refraction_rays;
    size_t total_internal_reflections;
    size_t cut_by_depth;     /**< secondary rays not traced: max_depth reached */
    size_t cut_by_weight;    /**< secondary rays not traced: weight below min_weight */
    uint32_t max_samples_per_pixel;
    double mean_samples_per_pixel;
    /** Estimated error of the image: per pixel the standard error of the mean
     *  of its samples' luminance (sample standard deviation / sqrt(n));
     *  max_error the largest over the pixels, mean_error their mean, method
     *  GEOM_ERROR_ESTIMATE (0 and GEOM_ERROR_NONE with one sample per pixel),
     *  evaluations = samples. */
    geom_error_report image_error;
    double seconds;
} geom_trace_report;

/**
 * Whitted ray tracing of a built ray-module scene: hit.object (the ray
 * scene's top-level object) indexes object_material (n_objects entries, each
 * < n_materials). Shadow rays, reflection and refraction rays start at
 * geom_ray_offset_origin. Texture coordinates are the hit's (u, v) (the
 * surface parameters or per-shape coordinates of the ray module; for meshes
 * barycentric, so textured meshes should go through geom_scene_render,
 * which interpolates their "uv" channel). Shadows: a shadow ray that meets
 * a surface whose material has transmit > 0 continues past it with its
 * light scaled by transmit (one factor per surface crossed, so a closed
 * glass object passes transmit^2; the ray is not refracted: no caustics,
 * no colour); an opaque hit blocks the light. Without transmissive
 * materials only "any hit" is asked. Statuses as geom_scene_raster.
 */
GEOM_API geom_status geom_scene_trace(const geom_ray_scene *rs, const uint32_t *object_material,
                                      size_t n_objects, const geom_camera *cam,
                                      const geom_light *lights, size_t n_lights,
                                      const geom_material *materials, size_t n_materials,
                                      const geom_trace_options *opt, geom_image *out,
                                      geom_trace_report *report);

/* ------------------------------------------------- whole-scene rendering */

/** World bounding box of a shape (its transform applied); unbounded shapes
 *  (planes, unclipped quadrics, CSG of them) give an infinite box. */
GEOM_API geom_aabb geom_scene_shape_bounds(const geom_shape *s);

/** Add s (and its CSG children, with their transforms) to a ray scene; *ids
 *  receives the top-level node ids (one per surface of a multi-surface
 *  object, else one) and *n_ids their count (ids: room for max(1,
 *  s->n_surfaces)). Statuses of the geom_ray_scene_add_* functions;
 *  GEOM_ERR_INVALID_ARG for a CSG child with several surfaces. */
GEOM_API geom_status geom_scene_shape_to_ray(geom_ray_scene *rs, const geom_shape *s,
                                             uint32_t *ids, size_t *n_ids, geom_diag *diag);

typedef struct geom_scene_object {
    const geom_shape *shape;
    uint32_t material;
} geom_scene_object;

typedef enum geom_render_method {
    GEOM_RENDER_RAY = 0,   /**< Whitted ray tracing through the ray module */
    GEOM_RENDER_RASTER = 1 /**< tessellate to the pixel error, then geom_scene_raster */
} geom_render_method;

typedef struct geom_render_options {
    geom_render_method method;
    geom_aov aov;
    geom_vec3 background;
    double pixel_error;       /**< raster: projected chordal error in pixels; 0 = 0.5 */
    double tolerance;         /**< raster: a fixed world tolerance instead (> 0) */
    uint32_t max_depth;       /**< ray: 0 = 8 */
    double min_weight;        /**< ray: 0 = 1/256 */
    int no_shadows;           /**< nonzero: no shadow rays / shadow maps */
    uint32_t shadow_map_size; /**< raster: 0 = 1024 */
    /** ray: called after each image row with the fraction done (NULL: none) */
    void (*progress)(void *user, double fraction);
    void *progress_user;
} geom_render_options;

/** What was built for one object, and why. */
typedef struct geom_render_object_report {
    int visible;          /**< its bounds meet the view frustum */
    int needed;           /**< some ray (or the rasterizer) can reach it: built */
    int acceleration;     /**< ray: a BVH was built for it (meshes, subdivision) */
    size_t accel_triangles;
    int tessellated;      /**< tessellated: raster always; ray only subdivision surfaces
                               and displaced objects */
    double tolerance;     /**< the chordal tolerance used when tessellated (world units) */
    geom_tess_info tess;  /**< what the tessellation achieved (error in world units,
                               times the transform's largest scale) */
    int normals, uvs, tangents; /**< attributes made (raster) or used (ray) */
    int displaced;        /**< the material's displacement map applied (both methods) */
} geom_render_object_report;

typedef struct geom_render_report {
    double seconds_build;     /**< bounds, reachability, ray scene build or tessellation */
    double seconds_render;
    size_t objects_needed;
    int refraction;           /**< some needed material transmits: refraction rays possible */
    int reflection;
    geom_ray_build_info ray_build;
    geom_trace_report trace;
    geom_raster_report raster;
} geom_render_report;

/**
 * Render objects (n_objects, each with a material index) with the camera and
 * lights, doing only the work the picture needs:
 *  - visibility: an object whose bounds miss the view frustum is not seen;
 *  - reachability: without reflective or refractive materials on seen
 *    objects, an unseen object matters only if it can shadow a seen one:
 *    its bounds meet the box hull of the seen objects and a point light
 *    (for a directional light: the seen objects swept toward it); objects
 *    that matter for nothing are not built (no BVH, no tessellation);
 *  - ray: analytic shapes are traced directly, never tessellated; BVHs are
 *    built only for needed meshes; texture coordinates only for textured
 *    materials (meshes: their corner or vertex "uv" channel, kept with the
 *    ray module's stored triangles and interpolated at the hit; corner
 *    normals likewise; polygon meshes are triangulated first), tangents only
 *    for normal/bump maps (meshes: dP/du of each triangle's UV map);
 *    refraction rays only where a material transmits; subdivision surfaces
 *    (refined until the limit is within the pixel tolerance below) and
 *    objects whose material displaces are tessellated as for raster, then
 *    traced as meshes;
 *  - raster: each needed object is tessellated with the tolerance that keeps
 *    its projected chordal error below pixel_error pixels at its nearest
 *    visible depth (geom_scene_pixel_tolerance, in its own frame through the
 *    transform's largest scale), with only the attributes its material uses,
 *    then displaced by the material's displacement map (geom_scene_displace).
 *  - shadows: a shadow ray is attenuated, not stopped, by transmissive
 *    materials: see geom_scene_trace.
 * object_reports (n_objects entries, may be NULL) and report (may be NULL)
 * say what was done. out as geom_scene_raster. Statuses: those of the steps;
 * diag names the object that failed.
 */
GEOM_API geom_status geom_scene_render(const geom_camera *cam, const geom_light *lights,
                                       size_t n_lights, const geom_material *materials,
                                       size_t n_materials, const geom_scene_object *objects,
                                       size_t n_objects, const geom_render_options *opt,
                                       geom_image *out, geom_render_report *report,
                                       geom_render_object_report *object_reports,
                                       geom_diag *diag);

/* ------------------------------------------------------------------ export */

typedef struct geom_export_options {
    double tolerance;    /**< > 0: this world tolerance for every object */
    double pixel_error;  /**< else from the camera (geom_scene_pixel_tolerance); 0 = 0.5 */
    geom_mat4 world;     /**< applied last (e.g. Z-up to glTF's Y-up); all zero = identity */
    double max_triangles; /**< geom_scene_export_estimate only: > 0: cheap upper
                               bounds for marching-cubes shapes first, the exact
                               trials only when their sum is above this; 0 = the
                               exact trials always */
} geom_export_options;

typedef struct geom_export_object_report {
    double tolerance;    /**< world tolerance asked */
    geom_tess_info tess; /**< achieved, the error in world units (times the
                              transform's largest scale) */
    unsigned attributes; /**< GEOM_NEEDS_* made for its material */
} geom_export_object_report;

/**
 * Tessellate every object (geom_scene_tessellate with the attributes its
 * material uses: normals always, UVs for textures and maps, tangents for
 * normal and bump maps) to its tolerance (opt->tolerance, else the camera's
 * pixel-error tolerance for its bounds; cam may be NULL only with a
 * tolerance), apply its transform and opt->world, and join them into `out`
 * (replaced): one face group per object named names[i] (may be NULL),
 * CORNER channels "normal", "uv" and "tangent" where some object's material
 * uses them (zero for the faces of objects that do not). Unbounded shapes
 * are cut to twice the box of the bounded ones and the eye. reports: n
 * entries or NULL. Statuses of geom_scene_tessellate (diag names the
 * object), GEOM_ERR_INVALID_ARG, GEOM_ERR_NOMEM.
 */
GEOM_API geom_status geom_scene_export(const geom_camera *cam, const geom_material *materials,
                                       size_t n_materials, const geom_scene_object *objects,
                                       size_t n, const char *const *names,
                                       const geom_export_options *opt, geom_mesh *out,
                                       geom_export_object_report *reports, geom_diag *diag);

/**
 * The triangles geom_scene_export would make with the same arguments,
 * before the work: each object's request (tolerance, attributes, extent)
 * as geom_scene_export forms it, and geom_scene_tessellate_estimate of it;
 * per_object (n doubles, NULL allowed) receives each object's estimate and
 * *triangles their sum (an estimate, not a bound: see
 * geom_scene_tessellate_estimate for each kind). With opt->max_triangles
 * > 0, quadrics, implicit surfaces, volumes and CSG get a cheap upper bound
 * first: no marching-cubes pass of geom_scene_tessellate's is done; its last
 * possible pass is assumed (the error of a pass is not known without
 * doing it) and that pass's count is scaled from one extraction on a
 * coarse grid (at most 32^3 cells and at most 1/16 of the first pass's, at
 * least 8^3) by the ratio of cells to the 2/3 (triangles follow the
 * surface's area, 1/h^2), times 1.5 (on a coarse grid the count follows
 * the area only roughly: without it the bound fell to 0.98 of the count).
 * Measured on spheres, tori, a gyroid, a capped cylinder, a CSG difference
 * and a volume from tol 1e-1 to 1e-3 of the size: 1.47 to 26 times the
 * triangles made (about 16 times more when the first pass already reaches
 * the tolerance), at most 0.13 of the tessellation's CPU on tessellations
 * of 20 ms or more (below 1 to 3 ms on the smaller). When the sum is at most
 * opt->max_triangles it is the answer (the output cannot be larger), else
 * every object is estimated again as geom_scene_tessellate_estimate does
 * (exact trials). geom-scene --export checks it against --max-triangles
 * and --max-memory before tessellating, passing the smaller of the two as
 * max_triangles.
 * Statuses: GEOM_OK; GEOM_ERR_INVALID_ARG (as geom_scene_export, or NULL
 * triangles; diag names the object), GEOM_ERR_NOMEM, geom_subdiv_mesh's.
 */
GEOM_API geom_status geom_scene_export_estimate(const geom_camera *cam,
                                                const geom_material *materials,
                                                size_t n_materials,
                                                const geom_scene_object *objects, size_t n,
                                                const geom_export_options *opt,
                                                double *per_object, double *triangles,
                                                geom_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* GEOM_SCENE_H */
