/* Private to the implicit module: the compiled program. Not installed. */
#ifndef GEOM_SRC_IMPLICIT_INTERNAL_H
#define GEOM_SRC_IMPLICIT_INTERNAL_H

#include "geom/implicit.h"
#include "core/internal.h"

/* Opcodes of the postfix program. Each pops its arguments off the
 * evaluation stack (the last argument on top) and pushes one result. */
typedef enum expr_op {
    OP_CONST, /* push c */
    OP_X, OP_Y, OP_Z, OP_T,
    OP_ADD, OP_SUB, OP_MUL, OP_DIV, OP_NEG,
    OP_POW,  /* a ^ b */
    OP_POWI, /* a ^ n, n = ins.n */
    OP_SQRT, OP_ABS, OP_SIN, OP_COS, OP_TAN, OP_EXP, OP_LOG,
    OP_MIN, OP_MAX, OP_CLAMP, OP_ATAN2,
    OP_SMIN, /* smin(a, b, k) */
    OP_SMAX, /* -smin(-a, -b, k) */
    OP_SPHERE1, OP_SPHERE4,
    OP_ELLIPSOID3, OP_ELLIPSOID6,
    OP_TORUS2, OP_TORUS5,
    OP_BOX3, OP_BOX6,
    OP_CYLINDER2, OP_CYLINDER5,
    OP_PLANE4,
    OP_CAPSULE7,
    OP_GYROID0, OP_GYROID1, OP_GYROID2,
    OP_COUNT
} expr_op;

typedef struct expr_ins {
    int op;   /* expr_op */
    int n;    /* OP_POWI exponent */
    double c; /* OP_CONST value */
} expr_ins;

struct geom_implicit_expr {
    expr_ins *code;
    size_t n;         /* instructions */
    size_t cap;       /* allocated instructions */
    size_t max_stack; /* deepest stack the program reaches */
    unsigned vars;    /* GEOM_IMPLICIT_VAR_* */
    double t;
    geom_allocator alloc;
};

/* Number of arguments an opcode pops (0 for pushes). */
int geom__implicit_op_arity(int op);

/* Point evaluation of a program fragment of n instructions needing at most
 * GEOM_IMPLICIT_STACK_MAX slots (used for constant folding). */
double geom__implicit_run_double(const expr_ins *code, size_t n, double x, double y, double z,
                            double t);

/* Marching squares' sparse path (contour_estimate.c): the grid of nx x ny
 * cells over bounds is cut into blocks of *block x *block cells (16, or
 * more so that the bitmap stays under 2^27 bytes); a block is active unless
 * field->bounds proves f - iso of one strict sign over it (recursive
 * halving, a quadtree over the blocks). *bits receives the row-major
 * bitmap of active blocks (nbx = ceil(nx / block) bits per block row,
 * rounded up to 64-bit words: *words_per_row), *cells the number of cells
 * in active blocks, *calls the bounds calls made. Without field->bounds
 * *bits is NULL and *cells = nx * ny. GEOM_OK or GEOM_ERR_NOMEM. */
geom_status geom__contour_blocks(const geom_implicit_field *field, const double bounds[4],
                                 size_t nx, size_t ny, double iso, double z,
                                 const geom_allocator *a, uint64_t **bits, size_t *words_per_row,
                                 size_t *block, double *cells, size_t *calls);
/* Free geom__contour_blocks' bitmap (rows block rows). */
void geom__contour_blocks_free(const geom_allocator *a, uint64_t *bits, size_t words_per_row,
                               size_t rows);
/* Node coordinate i of n cells over [a, b], as marching squares samples it. */
static inline double geom__contour_coord(double a, double b, size_t n, size_t i)
{
    return i == n ? b : (a * (double)(n - i) + b * (double)i) / (double)n;
}
/* geom_implicit_samples_value at n points p (3*n doubles) of d (its own
 * samples d->data) into out (n doubles), bitwise the same values, blocks of
 * points at a time (trilinear.c). */
void geom__implicit_samples_values(const geom_implicit_grid *d, size_t n, const double *p,
                                   double *out);

/* Values of e at the n points (x[i], y, z) of a grid row into out (n
 * doubles), bitwise geom_implicit_expr_eval at each point: y, z and the
 * primitives' y and z terms are computed once per block of points
 * (expr_eval.c, for marching cubes' sampling). e non-NULL. A row plan
 * (geom__implicit_expr_rows_create, with the allocator a, NULL: malloc)
 * is made once and serves every row of a grid (one thread at a time: it
 * holds the lanes); geom__implicit_expr_row makes one for its call (then
 * point by point when that fails). _create: GEOM_OK or GEOM_ERR_NOMEM; e
 * must outlive the plan. */
typedef struct geom__expr_rows geom__expr_rows;
geom_status geom__implicit_expr_rows_create(const geom_implicit_expr *e,
                                            const geom_allocator *a, geom__expr_rows **out);
void geom__implicit_expr_rows(geom__expr_rows *r, size_t n, const double *x, double y, double z,
                              double *out);
void geom__implicit_expr_rows_destroy(geom__expr_rows *r);
void geom__implicit_expr_row(const geom_implicit_expr *e, size_t n, const double *x, double y,
                             double z, double *out);
/* A box of blocks b0..b1 - 1 (dim axes; single: one block on every axis)
 * seen by geom__block_split: 1 to split it, 0 when it is done. */
typedef int (*geom__block_visit)(void *user, const size_t *b0, const size_t *b1, int single);
/* Recursive subdivision of the box of blocks b0..b1 - 1 (dim 2 or 3): visit
 * the box; unless it is done or single, halve every axis longer than one
 * block and split the 2^dim non-empty children in turn (block_split.c; the
 * block pruning of contour_estimate.c and iso/extract.c). */
void geom__block_split(int dim, const size_t *b0, const size_t *b1, geom__block_visit visit,
                       void *user);
/* Lanes per block of the batch interpolators (trilinear.c, volume_batch.c). */
#define GEOM__TRI_BLOCK 64
/* geom_implicit_samples_value's cell location along an axis with n >= 2
 * samples (umax = n - 1, origin o, spacing s) for GEOM__TRI_BLOCK
 * coordinates c, without branches: the same operations in the same order,
 * so the same cells i0 and fractions f. */
GEOM__CLONE_INLINE void geom__locate_lanes(const double *restrict c, double o, double s,
                                           double umax, int32_t *restrict i0,
                                           double *restrict f)
{
    for (int l = 0; l < GEOM__TRI_BLOCK; l++) {
        double u = (c[l] - o) / s;
        u = u > 0.0 ? u : 0.0;
        u = u > umax ? umax : u;
        double fl = (double)(int32_t)u; /* floor(u): 0 <= u < 2^31 */
        fl = fl >= umax ? umax - 1.0 : fl;
        f[l] = u - fl;
        i0[l] = (int32_t)fl;
    }
}

#endif
