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
/* Room needed by the masks of level p's vertices and edges (mask weights,
 * edge-end values): the most edges or faces at a vertex or an edge, + 2. */
static inline uint32_t sd_mask_room(const sd_level *p)
{
    return (p->max_valence > p->max_edge_faces ? p->max_valence : p->max_edge_faces) + 2;
}
/* The arguments of an interpolation into level `level` (1..max level). */
static inline geom_status sd_check_interp(const geom_subdiv_refiner *r, int level, size_t ncomp,
                                          const void *src, const void *dst)
{
    if (!r || !src || !dst || ncomp == 0 || level < 1 || level >= r->nlevels)
        return GEOM_ERR_INVALID_ARG;
    return GEOM_OK;
}
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

/* ------------------------------------------- applying masks (interp*.c, limit.c) */

/* The kernels are inlined into each caller, so a call with a constant
 * component count (3 for positions) or NULL index maps is compiled for it. */
#if defined(__GNUC__) || defined(__clang__)
#define SD_KERNEL static inline __attribute__((always_inline))
#else
#define SD_KERNEL static inline
#endif

/* d = w s and d += w s over n components. */
SD_KERNEL void sd_set_w(double *d, const double *s, double w, size_t n)
{
    if (n == 3) {
        d[0] = s[0] * w;
        d[1] = s[1] * w;
        d[2] = s[2] * w;
        return;
    }
    for (size_t k = 0; k < n; k++)
        d[k] = s[k] * w;
}

/* The smooth vertex-point weights of a vertex with n faces: Loop (Warren's
 * beta: each edge neighbour ew, the vertex vw) and Catmull-Clark (each
 * edge neighbour and each face point ew, the vertex vw). The vertex
 * masks (masks.c) and the direct smooth path of interp.c share them. */
static inline void sd_smooth_weights(int loop, uint32_t n, double *ew, double *vw)
{
    if (loop) {
        *ew = 0.0625;
        *vw = 0.625;
        if (n != 6) {
            double dn = (double)n, inv = 1.0 / dn;
            double c = cos(GEOM_PI * 2.0 * inv);
            double beta = 0.25 * c + 0.375;
            *ew = (0.625 - beta * beta) * inv;
            *vw = 1.0 - *ew * dn;
        }
        return;
    }
    *vw = (double)((int)n - 2) / (double)n;
    *ew = 1.0 / (double)(n * n);
}

/* d = 0 (n values): three stores for positions, not a call to memset per
 * vertex. */
static inline void sd_zero(double *d, size_t n)
{
    if (n == 3) {
        d[0] = d[1] = d[2] = 0.0;
        return;
    }
    for (size_t k = 0; k < n; k++)
        d[k] = 0.0;
}

SD_KERNEL void sd_add_w(double *d, const double *s, double w, size_t n)
{
    if (n == 3) {
        d[0] += s[0] * w;
        d[1] += s[1] * w;
        d[2] += s[2] * w;
        return;
    }
    for (size_t k = 0; k < n; k++)
        d[k] += s[k] * w;
}

/* Values made by stencils (CSR: value i = sum over j in off[i]..off[i+1]
 * of w[j] src[idx[j]]): butterfly and sqrt3 vertices, sqrt3 face-varying
 * values. */
static inline void sd_stencils_apply(uint32_t count, const uint32_t *off, const uint32_t *idx,
                                     const double *w, size_t n, const double *src, double *dst)
{
    for (uint32_t i = 0; i < count; i++) {
        double *d = dst + (size_t)i * n;
        sd_zero(d, n);
        for (uint32_t j = off[i]; j < off[i + 1]; j++)
            sd_add_w(d, src + (size_t)idx[j] * n, w[j], n);
    }
}

/* The same kernels serve vertex data and face-varying data: `val` maps the
 * level's face-vertices to source values (the level's own fv for vertex
 * data, a channel's fvals for face-varying data) and `at` maps the child
 * vertices made from faces to destination values (NULL: the identity; a
 * channel's vsib_off for face-varying data). */
static inline size_t sd_at(const uint32_t *at, uint32_t i) { return at ? at[i] : i; }

/* Face points: the mean of each face's values, at dst[at(f)]. */
SD_KERNEL void sd_face_points(const sd_level *p, size_t n, const uint32_t *val, const uint32_t *at,
                              const double *src, double *dst)
{
    for (uint32_t f = 0; f < p->nf; f++) {
        uint32_t o = p->fv_off[f], m = p->fv_off[f + 1] - o;
        double w = 1.0 / (double)m;
        double *d = dst + sd_at(at, f) * n;
        sd_zero(d, n);
        for (uint32_t i = 0; i < m; i++)
            sd_add_w(d, src + (size_t)val[o + i] * n, w, n);
    }
}

/* An edge point d from its edge mask m (end weights vw at the values ev)
 * over edge e of p: face weights on the face points (m->fcenters, at
 * dst[at(face)]) or on the vertex opposite the edge in each face. */
SD_KERNEL void sd_edge_apply(const sd_level *p, uint32_t e, const sd_mask *m, const double vw[2],
                             const uint32_t ev[2], size_t n, const uint32_t *val,
                             const uint32_t *at, const double *src, const double *dst, double *d)
{
    uint32_t fo = p->ef_off[e];
    sd_set_w(d, src + (size_t)ev[0] * n, vw[0], n);
    sd_add_w(d, src + (size_t)ev[1] * n, vw[1], n);
    for (int i = 0; i < m->nf; i++) {
        uint32_t f = p->ef[fo + (uint32_t)i];
        if (m->fcenters) {
            sd_add_w(d, dst + sd_at(at, f) * n, m->f[i], n);
        } else {
            uint32_t fvo = p->fv_off[f], fs = p->fv_off[f + 1] - fvo;
            uint32_t vi = p->ef_loc[fo + (uint32_t)i] + 2;
            if (vi >= fs)
                vi -= fs;
            sd_add_w(d, src + (size_t)val[fvo + vi] * n, m->f[i], n);
        }
    }
}

#endif
