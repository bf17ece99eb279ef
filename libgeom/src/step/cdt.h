/* Constrained Delaunay triangulation used by the trimmed-face mesher
 * (private to the step module; see cdt.c). */
#ifndef GEOM_SRC_STEP_CDT_H
#define GEOM_SRC_STEP_CDT_H

#include "core/internal.h"

#include <stdint.h>

typedef struct geom__cdt_tri {
    int32_t v[3];   /* counter-clockwise */
    int32_t n[3];   /* n[k]: neighbour across the edge opposite v[k], -1 none */
    uint8_t con[3]; /* con[k]: that edge is constrained */
    uint8_t dead;
    uint8_t inside;
} geom__cdt_tri;

typedef struct geom__cdt {
    const geom_allocator *a;
    double *xy; /* points 0..2 are the super triangle */
    size_t np, capp;
    geom__cdt_tri *tri;
    size_t nt, capt;
    int32_t *stack;
    size_t capstack;
    uint32_t *mark;
    size_t capmark;
    uint32_t stamp;
    int32_t last;
} geom__cdt;

/* A super triangle around box (xmin, xmax, ymin, ymax). */
geom_status geom__cdt_init(geom__cdt *c, const geom_allocator *a, const double box[4]);
void geom__cdt_free(geom__cdt *c);
/* Insert (x, y): *vid its index. GEOM_ERR_DEGENERATE (nothing inserted)
 * for a duplicate point (*vid = the existing one) or a point on a
 * constrained edge; GEOM_ERR_DOMAIN outside the super triangle. */
geom_status geom__cdt_insert(geom__cdt *c, double x, double y, int32_t *vid);
/* Make (a, b) an edge and mark it constrained (splitting at vertices on
 * it). GEOM_ERR_DEGENERATE if it crosses another constrained edge. */
geom_status geom__cdt_constrain(geom__cdt *c, int32_t a, int32_t b, int depth);
/* inside = 1 for triangles separated from the super triangle by an odd
 * number of constrained edges. */
void geom__cdt_classify(geom__cdt *c);
int32_t geom__cdt_locate(geom__cdt *c, const double q[2]);

#endif
