/* Private declarations of the iso module. */
#ifndef GEOM_SRC_ISO_INTERNAL_H
#define GEOM_SRC_ISO_INTERNAL_H

#include "geom/iso.h"
#include "core/internal.h"

#include <stdint.h>

/*
 * Cell conventions (used by every file of the module):
 *  - corner c in 0..7 sits at (x, y, z) = (c & 1, (c >> 1) & 1, c >> 2);
 *  - edges 0..3 run along x, at (y, z) = (0,0), (1,0), (0,1), (1,1);
 *    edges 4..7 along y at (x, z) = (0,0), (1,0), (0,1), (1,1);
 *    edges 8..11 along z at (x, y) = (0,0), (1,0), (0,1), (1,1);
 *    geom__iso_edge_corners[e] = {lower corner, upper corner};
 *  - faces 0..5 are x = 0, x = 1, y = 0, y = 1, z = 0, z = 1 (face f has the
 *    fixed axis f >> 1 at the side f & 1).
 * Values g are f - iso, with g <= 0 inside (the level iso + epsilon).
 */
extern const uint8_t geom__iso_edge_corners[12][2];
/** The corners of each face, counter-clockwise seen from outside the cell. */
extern const uint8_t geom__iso_face_corners[6][4];

/** Largest polygon geom__iso_polygon_tris handles. */
#define ISO_POLY_MAX 36

/**
 * Triangulate a polygon of n vertices (positions p[i], cell-face bit masks
 * fm[i], 0 for vertices on no face) without new vertices, keeping its
 * orientation: n = 3 as is, n = 4 along the shorter diagonal,
 * larger ones minimising the sum of squared areas (dynamic programming);
 * chords between two vertices of one cell face are avoided. Writes n - 2
 * triangles of polygon-local indices; returns their number. *forced is
 * set when every triangulation has such a chord (the caller should then
 * use an inner vertex instead).
 */
int geom__iso_polygon_tris(int n, const double *const p[], const unsigned fm[], uint8_t (*tri)[3],
                     int *forced);

/** Faces (bits 0..5) containing cell edge e. */
static inline unsigned iso_edge_faces(int e)
{
    static const uint8_t bits[12] = {
        /* x edges: (y, z) */ (1u << 2) | (1u << 4), (1u << 3) | (1u << 4),
        (1u << 2) | (1u << 5), (1u << 3) | (1u << 5),
        /* y edges: (x, z) */ (1u << 0) | (1u << 4), (1u << 1) | (1u << 4),
        (1u << 0) | (1u << 5), (1u << 1) | (1u << 5),
        /* z edges: (x, y) */ (1u << 0) | (1u << 2), (1u << 1) | (1u << 2),
        (1u << 0) | (1u << 3), (1u << 1) | (1u << 3)};
    return bits[e];
}

/** Per sign configuration (bit c: corner c outside): when no face is
 *  ambiguous and there is one contour (no interior question either), the
 *  contour's edges in order. Filled per extraction (no global state). */
typedef struct iso_case {
    uint8_t simple; /**< 1: use edges[0..n-1] */
    uint8_t n;
    uint8_t edges[12];
} iso_case;

typedef struct iso_case_table {
    iso_case cases[256];
} iso_case_table;

void geom__iso_case_table_init(iso_case_table *t);

/** Largest number of triangles and inner vertices one cell produces. */
#define ISO_CELL_MAX_TRIS 64
#define ISO_CELL_MAX_INNER 24

/** What geom__iso_cell_triangulate made for one cell. */
typedef struct iso_cell_result {
    int ntris;
    /** Vertex references: 0..11 the crossing vertex of that edge,
     *  12 + i the inner vertex i. Counter-clockwise seen from outside. */
    uint8_t tris[ISO_CELL_MAX_TRIS][3];
    int ninner;
    double inner[ISO_CELL_MAX_INNER][3]; /**< world positions of inner vertices */
    unsigned ambiguous;                  /**< bit f: face f was ambiguous */
    int tunnels;                         /**< tubes made */
} iso_cell_result;

/**
 * Triangulate one cell. g: the 8 corner values (f - iso, finite, inside when
 * <= 0); vpos: world positions of the crossing vertices, indexed by edge
 * (only read for edges whose corners differ in sign); lo, size: the cell's
 * lower corner and size (for inner vertices). The cell must be active (not
 * all corners on one side).
 */
void geom__iso_cell_triangulate(const double g[8], const double vpos[12][3], const double lo[3],
                          const double size[3], iso_cell_result *out);

/**
 * Asymptotic decider of a face whose canonical corners are g00, g10, g01,
 * g11 (the two free axes in increasing order, u fastest): 1 if the corners
 * 00 and 11 are joined through the face, 0 if 10 and 01 are. Only
 * meaningful for an ambiguous face. Symbolically perturbed for iso + eps.
 */
int geom__iso_face_decider(double g00, double g10, double g01, double g11);

/** For an ambiguous face f of a cell with corner values g: the joined
 *  diagonal (two corners) into joined, and 1 if they are inside corners,
 *  0 if outside ones. The same answer in both cells sharing the face. */
int geom__iso_face_join(int f, const double g[8], int joined[2]);

/** The inside corners of face f of a cell with corner values g (g <= 0
 *  inside): in[k] for the face's corners in geom__iso_face_corners order;
 *  returns their number, *changes the inside/outside changes around the
 *  face (4: an ambiguous face). The caps' rule (extract.c) and their count
 *  (estimate.c) start from it. */
int geom__iso_face_inside(int f, const double g[8], int in[4], int *changes);

/** Error accumulation. */
typedef struct iso_err_acc {
    double vmax, vsum;
    size_t vcount;
    double smax, ssum;
    size_t scount;
    size_t unmeasured;
    size_t evaluations;
} iso_err_acc;

/** Gradient of the field at p: the callback, else central differences
 *  with per-axis steps h (3 doubles). Adds evaluations to *evals. */
void geom__iso_field_gradient(const geom_iso_field *f, const double p[3], const double h[3],
                        double g[3], size_t *evals);

/** |f(p) - iso| / |grad f(p)| into *e; returns 0 if not measurable. */
int geom__iso_point_error(const geom_iso_field *f, double iso, const double p[3], const double h[3],
                    double *e, size_t *evals);

/** Error over nv vertices (those with vmask[v] != 0 when vmask is given)
 *  and nt triangles (fixed chunks, deterministic whatever the thread
 *  count), only the indices that are multiples of stride (0 = 1);
 *  h: central-difference steps. */
geom_status geom__iso_measure(const geom_iso_field *f, double iso, size_t nv, const double *xyz,
                              const uint8_t *vmask, size_t nt, const uint32_t *tris,
                              size_t stride, const double h[3], int threads,
                              const geom_allocator *alloc, iso_err_acc *total);

/** Sample (i, j, k) of a checked grid, as a double. */
static inline double iso_grid_at(const geom_iso_grid *g, size_t i, size_t j, size_t k)
{
    size_t idx = i + g->dims[0] * (j + g->dims[1] * k);
    if (g->type == GEOM_ISO_SCALAR_F32)
        return (double)((const float *)g->data)[idx];
    return ((const double *)g->data)[idx];
}

#endif
