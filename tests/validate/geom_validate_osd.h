/*
 * geom_validate, OpenSubdiv part: reference subdivision from OpenSubdiv 3's
 * Far (Debian libosd-dev), for the subdiv tests and benchmark.
 *
 * A shape (polygon soup, OpenSubdiv-style tags and an optional face-varying
 * channel) is refined uniformly with Far::TopologyRefinerFactory<
 * TopologyDescriptor> and Far::PrimvarRefinerReal<double>, child vertices
 * ordered face points first (UniformOptions::orderVerticesFromFacesFirst),
 * the last level with full topology so PrimvarRefiner::Limit works. Tags are
 * interpreted as OpenSubdiv's regression harness (regression/common/
 * shape_utils.h: GetSdcOptions and assignComponentTags) does: boundary edge
 * only, uniform creasing, Catmull-Clark triangles and linear face-varying
 * interpolation unless a tag says otherwise; crease sharpness per pair when
 * a tag lists one value per pair (the harness indexes its float list with
 * the integer index, which differs only for tags with several values, which
 * no regression shape has); sharpness clamped to >= 0; hierarchical edits
 * ignored.
 *
 * Nothing here prints, throws across the C interface (exceptions become
 * NULL / GV_OSD_ERR) or keeps global state. Far's own error callback is left
 * as installed (OpenSubdiv's default prints Far errors to stderr).
 */
#ifndef GEOM_VALIDATE_OSD_H
#define GEOM_VALIDATE_OSD_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define GV_OSD_OK 0
#define GV_OSD_ERR (-1)

/** Schemes as Sdc::SchemeType. */
#define GV_OSD_BILINEAR 0
#define GV_OSD_CATMARK 1
#define GV_OSD_LOOP 2

/** One `t name nint/nfloat/nstring ...` tag. */
typedef struct gv_osd_tag {
    const char *name;
    size_t nint, nfloat, nstring;
    const int64_t *ints;
    const double *floats;
    const char *const *strings;
} gv_osd_tag;

typedef struct gv_osd_shape {
    int scheme;                 /**< GV_OSD_* */
    size_t nverts;
    const double *positions;    /**< 3 * nverts */
    size_t nfaces;
    const uint32_t *face_sizes; /**< nfaces */
    const uint32_t *indices;    /**< sum of face_sizes */
    size_t ntags;
    const gv_osd_tag *tags;
    /** Optional face-varying channel (2 doubles per value): values and one
     *  value index per face-vertex. n_fvar_values 0: none. */
    size_t n_fvar_values;
    const double *fvar_values;
    const uint32_t *fvar_indices;
} gv_osd_shape;

typedef struct gv_osd gv_osd;

/**
 * Refine `shape` uniformly to `levels` (0..10) and compute the positions of
 * every level, the limit positions and tangents of the last level, and the
 * face-varying values of every level and their limit. NULL on failure
 * (invalid shape, Far refusing the topology, out of memory); err (may be
 * NULL) receives a message.
 */
gv_osd *gv_osd_create(const gv_osd_shape *shape, int levels, char *err, size_t errlen);
void gv_osd_destroy(gv_osd *h);

size_t gv_osd_vertices(const gv_osd *h, int level);
size_t gv_osd_faces(const gv_osd *h, int level);
size_t gv_osd_face_vertices(const gv_osd *h, int level);
/** Face sizes (faces entries) and vertex indices (face_vertices entries) of a
 *  level; either may be NULL. */
int gv_osd_topology(const gv_osd *h, int level, uint32_t *sizes, uint32_t *indices);
/** Edges of a level: vertex pairs (2 per edge) and sharpness (1 per edge),
 *  vertex sharpness and rules (Sdc::Crease::Rule bits) per vertex, and hole
 *  flags per face; any array may be NULL. */
size_t gv_osd_edges(const gv_osd *h, int level);
int gv_osd_tags(const gv_osd *h, int level, uint32_t *edge_verts, float *edge_sharpness,
                float *vertex_sharpness, uint8_t *vertex_rule, uint8_t *face_hole);
/** Positions of a level (3 per vertex); NULL if out of range. */
const double *gv_osd_positions(const gv_osd *h, int level);
/** Limit positions and tangents (3 per vertex of the last level). The
 *  tangents are NULL for shapes with an edge of more than two faces: Far
 *  3.5's PrimvarRefiner::Limit with tangents overruns its weight buffer at
 *  the vertices of such edges. */
const double *gv_osd_limit(const gv_osd *h);
const double *gv_osd_limit_tan1(const gv_osd *h);
const double *gv_osd_limit_tan2(const gv_osd *h);
/** Face-varying values of a level (2 per value), the value of each
 *  face-vertex, and the limit of the last level's values. */
size_t gv_osd_fvar_values(const gv_osd *h, int level);
const double *gv_osd_fvar(const gv_osd *h, int level);
int gv_osd_fvar_indices(const gv_osd *h, int level, uint32_t *indices);
const double *gv_osd_fvar_limit(const gv_osd *h);
/** The Sdc options used, as integers: vertex boundary (0 none, 1 edge only,
 *  2 edge and corner), face-varying linear interpolation (0 none .. 5 all),
 *  creasing (0 uniform, 1 Chaikin), triangle subdivision (0 catmark, 1
 *  smooth). */
void gv_osd_options(const gv_osd *h, int *vtx, int *fvar, int *crease, int *tri);

#ifdef __cplusplus
}
#endif

#endif
