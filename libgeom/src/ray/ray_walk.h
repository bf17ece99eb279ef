/* The shape walk: what other modules of the library (scene) read of a ray
 * scene's nodes, as named fields, without the ray module's node struct.
 * Library-internal (not installed, not exported). */
#ifndef GEOM_SRC_RAY_WALK_H
#define GEOM_SRC_RAY_WALK_H

#include "geom/ray.h"

/* One node as it was added (transform, parameters, children). Pointers are
 * borrowed from the scene and live as long as it does. */
typedef struct geom__ray_node_info {
    geom_ray_kind kind;
    const char *name;             /* "" when unnamed */
    const double *xf;             /* 16 doubles, object to parent (column-major), or NULL */
    /* analytic shapes */
    double center[3], normal[3], radius; /* sphere, plane (center = point), disk */
    double min[3], max[3];        /* box */
    double axes[9], half[3];      /* oriented box: center, axes (columns), half extents */
    double major, minor;          /* torus */
    double q[10];                 /* quadric */
    double clip[6];               /* quadric clip box (min, max) when has_clip */
    int has_clip, capped;
    const double *verts;          /* triangle (3) and polygon vertices, 3 * nverts */
    size_t nverts;
    /* meshes and subdivision surfaces: the triangles traced */
    const double *pos, *nrm;      /* 3 * nv; nrm (vertex normals) may be NULL */
    size_t nv;
    const uint32_t *tri;          /* 3 * nt */
    const uint32_t *face;         /* nt: the face each triangle came from (reported as prim), or
                                     NULL: the triangle index itself */
    size_t nt;
    const double *cuv;            /* 6 * nt corner UVs (per triangle corner) or NULL */
    const double *cnrm;           /* 9 * nt corner normals or NULL */
    const geom_mesh *control;     /* subdivision: the control mesh, or NULL */
    int scheme, levels;           /* subdivision: scheme, levels asked (0 = default) */
    /* other representations */
    const geom_nurbs_surface *surface;
    const geom_implicit_expr *expr;
    double bounds[6];             /* implicit: min, max */
    const geom_implicit_volume *volume;
    double iso;
    int inside;                   /* volume: 1 when f > iso is inside */
    /* CSG, instances, groups */
    int op;                       /* geom_ray_csg_op */
    uint32_t a, b;                /* CSG children; a = instance target */
    const uint32_t *members;
    size_t nmembers;
} geom__ray_node_info;

/* Node id of s into *out. GEOM_ERR_INVALID_ARG for NULL or an id out of range. */
geom_status geom__ray_scene_node_info(const geom_ray_scene *s, uint32_t id,
                                      geom__ray_node_info *out);

/* The top-level objects (geom_ray_scene_set_objects' list, else every node
 * that is no CSG or group member, in id order), built or not: their count,
 * and ids[0 .. min(count, cap)) written (ids may be NULL with cap 0). */
size_t geom__ray_scene_top(const geom_ray_scene *s, uint32_t *ids, size_t cap);

#endif
