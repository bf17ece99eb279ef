/*
 * Shared by the sources of geom_mesh_build: build.c (arguments, the choice
 * of path, attribute streams), build_fast.c (input that is already an
 * oriented manifold: the common case, tried first) and build_repair.c (the
 * repairing path, steps 1-7). Not installed.
 */
#ifndef GEOM_SRC_MESH_BUILD_INTERNAL_H
#define GEOM_SRC_MESH_BUILD_INTERNAL_H

#include "mesh/mesh_internal.h"

/* Scratch blocks of one build, all freed together. */
typedef struct geom__mesh_bscratch {
    const geom_allocator *a;
    void *p[24];
    size_t sz[24];
    int n;
} geom__mesh_bscratch;

/* n elements of es bytes (n = 0 allocates one); NULL when out of memory. */
void *geom__mesh_bs_alloc(geom__mesh_bscratch *s, size_t n, size_t es);
/* Free one block early (p from geom__mesh_bs_alloc on s). */
void geom__mesh_bs_free_one(geom__mesh_bscratch *s, void *p);
void geom__mesh_bs_free_all(geom__mesh_bscratch *s);

/* Count an element in a report (*count) and keep the first few in first. */
void geom__mesh_report_add(size_t *count, uint32_t *first, uint32_t idx);

/* One edge per glued pair or unglued use, in the order of its first corner;
 * corner c becomes halfedge he_of[c] (2e for the first use, 2e + 1 for its
 * partner). Returns the halfedge count. Shared by both paths, so that they
 * number alike. */
size_t geom__mesh_number_edges(size_t C, const uint32_t *partner, uint32_t *he_of);

/* Returned by geom__mesh_build_fast when the input needs the repairing path. */
#define GEOM_MESH__NEEDS_REPAIR 1

/*
 * The build for input that is an oriented manifold mesh (see build_fast.c).
 * Returns 0 with *st set (GEOM_OK, or an allocation failure: m is then
 * empty), or GEOM_MESH__NEEDS_REPAIR (m cleared, *st GEOM_OK).
 */
int geom__mesh_build_fast(geom_mesh *m, size_t nverts, const double *xyz, size_t nfaces,
                          const uint32_t *face_sizes, const uint32_t *indices,
                          geom_mesh_build_report *rep, geom_status *st);

/* The repairing build (steps 1-7, see build_repair.c). Arguments are checked
 * by the caller; rep is zeroed. */
geom_status geom__mesh_build_repair(geom_mesh *m, size_t nverts, const double *xyz,
                                    size_t nfaces, const uint32_t *face_sizes,
                                    const uint32_t *indices, int skip, int keep,
                                    geom_mesh_build_report *rep, geom_diag *diag);

/* Face cycles with their edges numbered by the caller, for
 * geom__mesh_build_cycles. */
typedef struct geom__mesh_cycles {
    size_t nv;               /* vertices */
    const double *xyz;       /* 3 * nv doubles, finite */
    size_t nf;               /* faces */
    const uint32_t *fv_off;  /* nf + 1 offsets into fv and fe */
    const uint32_t *fv;      /* corner vertices, each face in order */
    const uint32_t *fe;      /* per corner: the edge to the next corner (< ne) */
    size_t ne;               /* edges */
    uint32_t max_face_size;
} geom__mesh_cycles;

/* Returned by geom__mesh_build_cycles for faces that are not an oriented
 * manifold whose vertex pairs name one edge each (m is then empty). */
#define GEOM_MESH__CYCLES_DECLINED 1

/*
 * Make the empty mesh m of the faces c (positions c->xyz), exactly the mesh
 * geom_mesh_build makes of them when they form an oriented manifold in which
 * each vertex has one fan (the caller knows it; debug builds check it), and
 * attach the streams chans[0..nchans) as geom_mesh_build does (identity
 * origin maps). Every edge is checked (at most two uses, in opposite
 * directions, never twice in one face); otherwise GEOM_MESH__CYCLES_DECLINED
 * and the caller builds through geom_mesh_build. GEOM_OK,
 * GEOM_MESH__CYCLES_DECLINED, GEOM_ERR_NOMEM (m empty). build_cycles.c.
 */
geom_status geom__mesh_build_cycles(geom_mesh *m, const geom__mesh_cycles *c,
                                    const geom_mesh_build_channel *chans, size_t nchans);

#endif
