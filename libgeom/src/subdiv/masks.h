/* Subdivision and limit masks (after OpenSubdiv's Sdc::Scheme). Private. */
#ifndef GEOM_SRC_SUBDIV_MASKS_H
#define GEOM_SRC_SUBDIV_MASKS_H

#include "subdiv_internal.h"

/* A mask: weights of the vertex itself, of the vertices at the other end of
 * its edges (in vertex-edge order) and of its faces (face centres, or the
 * vertex opposite in the face when fcenters is 0), in vertex-face order. */
typedef struct sd_mask {
    double v;
    double *e;
    double *f;
    int ne, nf;
    int fcenters;
} sd_mask;

/* Scratch for the vertex masks: room for a child mask and sharpness values
 * of a vertex of valence up to max_valence. */
typedef struct sd_scratch {
    double *w;    /* 2 * (max_valence + 1) */
    float *s;     /* 2 * (max_valence + 1) */
    uint32_t cap; /* max_valence + 1 */
} sd_scratch;

geom_status sd_scratch_init(const geom_allocator *a, sd_scratch *s, uint32_t max_valence);
void sd_scratch_free(const geom_allocator *a, sd_scratch *s);

/* Edge-vertex mask of parent edge e (vertex weights in v0w[2]); pRule from
 * the edge's sharpness, cRule the child vertex's rule. m->f needs room for
 * the edge's faces. */
void sd_edge_mask(const sd_opts *o, const sd_level *p, uint32_t e, int cRule, double vw[2],
                  sd_mask *m);

/* Vertex-vertex mask of parent vertex pv (child cv in c). m->e/m->f need
 * room for the vertex's edges/faces. */
void sd_vertex_mask(const sd_opts *o, const sd_level *p, const sd_level *c, uint32_t pv,
                    uint32_t cv, sd_mask *m, sd_scratch *s);

/* Limit masks of vertex v of level l with its rule: position, and tangents
 * when t1 and t2 are not NULL. Face weights are for opposite vertices. */
void sd_limit_masks(const sd_opts *o, const sd_level *l, uint32_t v, sd_mask *pos, sd_mask *t1,
                    sd_mask *t2, sd_scratch *s);

#endif
