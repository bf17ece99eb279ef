/*
 * Private representation of the subdivision hierarchy: one sd_level per
 * level with the full topology (after OpenSubdiv's Vtr::Level), sharpness,
 * tags and rules, and per face-varying channel an sd_fvar (after
 * Vtr::FVarLevel). Refinement is uniform, so parent-to-child maps are
 * implicit (see sd_child_* below).
 */
#ifndef GEOM_SRC_SUBDIV_INTERNAL_H
#define GEOM_SRC_SUBDIV_INTERNAL_H

#include "geom/subdiv.h"
#include "core/internal.h"

/* The module's internal functions are external symbols of the library:
 * give them the library's prefix (geom_<module>__, as the mesh module). */
#define sd_alloc geom__subdiv_alloc
#define sd_butterfly_stencils geom__subdiv_butterfly_stencils
#define sd_calloc geom__subdiv_calloc
#define sd_complete_level geom__subdiv_complete_level
#define sd_crease_pair geom__subdiv_crease_pair
#define sd_decrement geom__subdiv_decrement
#define sd_edge_mask geom__subdiv_edge_mask
#define sd_find_edge geom__subdiv_find_edge
#define sd_fractional_weight geom__subdiv_fractional_weight
#define sd_free geom__subdiv_free
#define sd_fvar_free geom__subdiv_fvar_free
#define sd_fvar_level0 geom__subdiv_fvar_level0
#define sd_fvar_refine geom__subdiv_fvar_refine
#define sd_level0_build geom__subdiv_level0_build
#define sd_level0_tags geom__subdiv_level0_tags
#define sd_level_complete geom__subdiv_level_complete
#define sd_level_count geom__subdiv_level_count
#define sd_level_free geom__subdiv_level_free
#define sd_limit_masks geom__subdiv_limit_masks
#define sd_malloc geom__subdiv_malloc
#define sd_mesh_direct geom__subdiv_mesh_direct
#define sd_mesh_direct_applies geom__subdiv_mesh_direct_applies
#define sd_refine_level geom__subdiv_refine_level
#define sd_refine_sqrt3 geom__subdiv_refine_sqrt3
#define sd_rule_from_count geom__subdiv_rule_from_count
#define sd_rule_from_edges geom__subdiv_rule_from_edges
#define sd_scratch_free geom__subdiv_scratch_free
#define sd_scratch_init geom__subdiv_scratch_init
#define sd_sqrt3_alpha geom__subdiv_sqrt3_alpha
#define sd_subdivide_edge_at_vertex geom__subdiv_subdivide_edge_at_vertex
#define sd_subdivide_edges_around geom__subdiv_subdivide_edges_around
#define sd_vertex_mask geom__subdiv_vertex_mask
#define sd_vertex_rule geom__subdiv_vertex_rule

#include <string.h>

#define SD_INVALID UINT32_MAX
#define SD_VALENCE_LIMIT 65535u
#define SD_SHARP_INF 10.0f

/* Rules (bits, as Sdc::Crease::Rule). */
#define SD_RULE_UNKNOWN 0
#define SD_RULE_SMOOTH 1
#define SD_RULE_DART 2
#define SD_RULE_CREASE 4
#define SD_RULE_CORNER 8

/* Edge tags. */
#define SD_E_BOUNDARY 1u
#define SD_E_NONMANIFOLD 2u
#define SD_E_INFSHARP 4u
#define SD_E_SEMISHARP 8u

/* Vertex tags: the rule in the low 4 bits. */
#define SD_V_RULE 0x0fu
#define SD_V_BOUNDARY 0x10u
#define SD_V_NONMANIFOLD 0x20u
#define SD_V_INFSHARP 0x40u
#define SD_V_SEMISHARP 0x80u
#define SD_V_SEMISHARP_EDGES 0x100u
#define SD_V_INFSHARP_EDGES 0x200u

/* Face-varying edge tags. */
#define SD_FE_MISMATCH 1u
#define SD_FE_DISCTS_V0 2u
#define SD_FE_DISCTS_V1 4u
#define SD_FE_LINEAR 8u

/* Face-varying value tags. */
#define SD_FV_MISMATCH 1u
#define SD_FV_XORDINARY 2u
#define SD_FV_NONMANIFOLD 4u
#define SD_FV_CREASE 8u
#define SD_FV_SEMISHARP 16u
#define SD_FV_DEPSHARP 32u

/* Options as OpenSubdiv's Sdc enums. */
enum { SD_VTX_NONE = 0, SD_VTX_EDGE_ONLY = 1, SD_VTX_EDGE_AND_CORNER = 2 };
enum {
    SD_FVAR_NONE = 0,
    SD_FVAR_CORNERS_ONLY = 1,
    SD_FVAR_CORNERS_PLUS1 = 2,
    SD_FVAR_CORNERS_PLUS2 = 3,
    SD_FVAR_BOUNDARIES = 4,
    SD_FVAR_ALL = 5
};

typedef struct sd_opts {
    int scheme;    /* geom_subdiv_scheme */
    int vtx;       /* SD_VTX_* */
    int fvar;      /* SD_FVAR_* */
    int chaikin;   /* 0 uniform, 1 chaikin */
    int smooth_tri; /* Catmull-Clark smooth triangle weights */
} sd_opts;

/* A face-varying channel at one level. */
typedef struct sd_fvar {
    uint32_t nvalues;      /* values addressed by fvals (level 0: the user's pool) */
    uint32_t *fvals;       /* per face-vertex value */
    uint8_t *etag;         /* per edge SD_FE_* */
    uint16_t *vsib_count;  /* per vertex: number of values (siblings) */
    uint32_t *vsib_off;    /* per vertex: first slot */
    uint16_t *vf_sib;      /* per vertex-face entry: sibling index of that face */
    uint32_t nslots;       /* total vertex values */
    uint32_t *slot_value;  /* per slot: the value (level 0: pool index; else = slot) */
    uint8_t *slot_tag;     /* per slot SD_FV_* */
    uint16_t *crease_ends; /* per slot: start face, end face (local to the vertex) */
    uint16_t *parent_src;  /* per slot (child levels): sibling/edge-face it comes from */
    /* sqrt3 child levels: each value as a combination of parent values */
    uint32_t *st_off, *st_idx;
    double *st_w;
    int is_linear, linear_boundaries, dependent_sharpness;
} sd_fvar;

typedef struct sd_level {
    uint32_t nv, ne, nf;
    int depth;
    uint32_t *fv_off;      /* nf + 1 */
    uint32_t *fv, *fe;     /* fv_off[nf] each */
    uint32_t *ev;          /* 2 * ne */
    uint32_t *ef_off, *ef; /* ne + 1, edge-faces */
    uint16_t *ef_loc;      /* edge's index in that face */
    uint32_t *vf_off, *vf; /* nv + 1, vertex-faces */
    uint16_t *vf_loc;      /* vertex's index in that face */
    uint32_t *ve_off, *ve; /* nv + 1, vertex-edges */
    uint16_t *ve_loc;      /* vertex's index (0/1) in that edge */
    float *esharp, *vsharp;
    uint8_t *etag;
    uint16_t *vtag;
    uint8_t *fhole;
    uint32_t *face_parent; /* depth > 0: parent face of each face */
    uint32_t max_valence, max_edge_faces, max_face_size;
    int complete;          /* incidence relations present: SD_REL_* (0 none) */
    uint32_t n_sharp_edges, n_hole_faces; /* counted when the level is made */
    uint32_t nfvar;
    sd_fvar *fvar;         /* nfvar channels */
    /* Generic schemes (butterfly, sqrt3): child vertex stencils from the
     * parent level, CSR (off: nv+1); and face-varying corner stencils. */
    uint32_t *st_off, *st_idx;
    double *st_w;
    uint32_t *vparent;     /* generic schemes: origin kind << 30 | parent index */
} sd_level;

struct geom_subdiv_refiner {
    geom_allocator alloc;
    int has_alloc;
    sd_opts o;
    geom_subdiv_options opt; /* effective public options (arrays cleared) */
    int nlevels;             /* levels present (max_level + 1) */
    sd_level *lv[GEOM_SUBDIV_MAX_LEVEL + 1];
    int has_holes;
    /* The mesh CORNER channel of each face-varying channel (mesh refiners). */
    uint32_t n_fvar_mesh;
    uint32_t fvar_mesh_channel[64];
};

/* ----- allocation helpers (through the refiner's allocator) */
const geom_allocator *sd_alloc(const geom_subdiv_refiner *r);
void *sd_calloc(const geom_allocator *a, size_t n, size_t size);
void *sd_malloc(const geom_allocator *a, size_t n, size_t size); /* not zeroed */
void sd_free(const geom_allocator *a, void *p, size_t n, size_t size);
void sd_level_free(const geom_allocator *a, sd_level *l);
void sd_fvar_free(const geom_allocator *a, const sd_level *l, sd_fvar *f);

/* ----- level 0 */
geom_status sd_level0_build(const geom_allocator *a, uint32_t nv, uint32_t nf,
                            const uint32_t *sizes, const uint32_t *idx, sd_level **out,
                            geom_diag *diag);
uint32_t sd_find_edge(const sd_level *l, uint32_t v0, uint32_t v1);
/* Tags (sharpness and rules) of level 0 after the user's sharpness was set. */
void sd_level0_tags(sd_level *l, const sd_opts *o, int *has_holes);
/* Count the level's sharp edges and hole faces (for level_info). */
void sd_level_count(sd_level *l);

/* ----- refinement */
/* Which incidence relations a child level gets (sd_level.complete). */
#define SD_REL_NONE 0  /* none: enough to interpolate into the level */
#define SD_REL_FULL 1  /* all: to refine it further, face-varying data */
#define SD_REL_LIMIT 2 /* vertex-edges and vertex-faces: geom_subdiv_limit */
/* Refine p into *out with the child's relations `rel` (SD_REL_*; face-
 * varying channels and butterfly always get SD_REL_FULL); otherwise
 * sd_complete_level adds them later. */
geom_status sd_refine_level(const geom_allocator *a, const sd_opts *o, const sd_level *p,
                            int rel, sd_level **out);
/* Give child level c of p the relations `mode` (SD_REL_FULL or
 * SD_REL_LIMIT; a level with all of them keeps them). */
geom_status sd_complete_level(const geom_allocator *a, const sd_opts *o, const sd_level *p,
                              sd_level *c, int mode);
/* Child index helpers for the split schemes (uniform refinement, face
 * points first). */
static inline int sd_quad_split(const sd_opts *o)
{
    return o->scheme == GEOM_SUBDIV_CATMULL_CLARK || o->scheme == GEOM_SUBDIV_BILINEAR;
}
static inline uint32_t sd_child_of_face(const sd_opts *o, const sd_level *p, uint32_t f)
{
    (void)p;
    return sd_quad_split(o) ? f : SD_INVALID;
}
static inline uint32_t sd_child_of_edge(const sd_opts *o, const sd_level *p, uint32_t e)
{
    return (sd_quad_split(o) ? p->nf : 0) + e;
}
static inline uint32_t sd_child_of_vert(const sd_opts *o, const sd_level *p, uint32_t v)
{
    return (sd_quad_split(o) ? p->nf : 0) + p->ne + v;
}

/* ----- creasing (Sdc::Crease) */
static inline int sd_is_smooth(float s) { return s <= 0.0f; }
static inline int sd_is_sharp(float s) { return s > 0.0f; }
static inline int sd_is_inf(float s) { return s >= SD_SHARP_INF; }
static inline int sd_is_semi(float s) { return s > 0.0f && s < SD_SHARP_INF; }
float sd_decrement(float s);
int sd_rule_from_count(float vsharp, int sharp_edges);
int sd_rule_from_edges(float vsharp, int n, const float *es);
float sd_subdivide_edge_at_vertex(int chaikin, float es, int n, const float *around);
void sd_subdivide_edges_around(int chaikin, int n, const float *p, float *c);
float sd_fractional_weight(int chaikin, float pv, float cv, int n, const float *pe,
                           const float *ce);
void sd_crease_pair(const float *es, int n, int ends[2]);

/* ----- face-varying topology */
geom_status sd_fvar_level0(const geom_allocator *a, const sd_level *l, const sd_opts *o,
                           uint32_t nvalues, const uint32_t *face_values, sd_fvar *out);
geom_status sd_fvar_refine(const geom_allocator *a, const sd_opts *o, const sd_level *p,
                           const sd_fvar *pf, const sd_level *c, sd_fvar *cf);

/* ----- generic schemes */
geom_status sd_butterfly_stencils(const geom_allocator *a, const sd_level *p, sd_level *c);
geom_status sd_refine_sqrt3(const geom_allocator *a, const sd_opts *o, const sd_level *p,
                            sd_level **out);
geom_status sd_level_complete(const geom_allocator *a, sd_level *l, geom_diag *diag);
double sd_sqrt3_alpha(uint32_t n);

/* ----- the output mesh of a level without a rebuild (mesh_direct.c) */
/* Whether level `level` of r (no holes assumed) can be built directly: an
 * oriented manifold whose vertex pairs name one edge each (from level 0's
 * tags; Catmull-Clark, bilinear and Loop levels >= 1). */
int sd_mesh_direct_applies(const geom_subdiv_refiner *r, int level);
/* Returned by sd_mesh_direct when the level is not such a mesh after all
 * (m is then empty): build from the soup instead. */
#define SD_DIRECT_DECLINED 1
/* The topology and positions (3 per vertex, finite) of level l into the
 * empty mesh m, exactly as geom_mesh_build would make them from the
 * level's faces, with the streams chans attached as geom_mesh_build
 * attaches them (identity origin maps; corner indices in the level's face
 * order). GEOM_OK, SD_DIRECT_DECLINED, GEOM_ERR_NOMEM. */
geom_status sd_mesh_direct(const sd_level *l, const double *positions,
                           const geom_mesh_build_channel *chans, size_t nchans, geom_mesh *m);

/* ----- masks for limit evaluation (limit.c) */
int sd_vertex_rule(const sd_level *l, uint32_t v);

#endif
