/*
 * Output size of marching squares before contouring: the field sampled on
 * a coarse grid, its crossing cells counted and scaled to the requested
 * resolution (the iso module's geom_iso_estimate_triangles in 2D).
 */
#include "implicit/implicit_internal.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* Coarse cells per axis at most. */
#define COARSE 64

/* The arguments both estimates take, as geom_implicit_contour checks them. */
static geom_status check_args(const geom_implicit_field *field, const double bounds[4], size_t nx,
                              size_t ny, const geom_implicit_contour_options *opt)
{
    double iso = opt ? opt->iso : 0.0, z = opt ? opt->z : 0.0;
    if (!field || !field->value || !bounds || nx == 0 || ny == 0 || !isfinite(iso) ||
        !isfinite(z))
        return GEOM_ERR_INVALID_ARG;
    for (int k = 0; k < 4; k++)
        if (!isfinite(bounds[k]))
            return GEOM_ERR_INVALID_ARG;
    if (!(bounds[0] < bounds[2]) || !(bounds[1] < bounds[3]))
        return GEOM_ERR_INVALID_ARG;
    return GEOM_OK;
}

geom_status geom_implicit_contour_estimate(const geom_implicit_field *field,
                                           const double bounds[4], size_t nx, size_t ny,
                                           const geom_implicit_contour_options *opt,
                                           double *vertices)
{
    if (!vertices)
        return GEOM_ERR_INVALID_ARG;
    *vertices = 0.0;
    double iso = opt ? opt->iso : 0.0, z = opt ? opt->z : 0.0;
    if (check_args(field, bounds, nx, ny, opt) != GEOM_OK)
        return GEOM_ERR_INVALID_ARG;
    size_t cx = nx < COARSE ? nx : COARSE, cy = ny < COARSE ? ny : COARSE;
    double prev[COARSE + 1], cur[COARSE + 1];
    size_t crossing = 0;
    for (size_t j = 0; j <= cy; j++) {
        double y = bounds[1] + (bounds[3] - bounds[1]) * (double)j / (double)cy;
        for (size_t i = 0; i <= cx; i++) {
            double p[3] = {bounds[0] + (bounds[2] - bounds[0]) * (double)i / (double)cx, y, z};
            cur[i] = field->value(field->user, p) - iso;
        }
        if (j > 0)
            for (size_t i = 0; i < cx; i++) {
                double v[4] = {prev[i], prev[i + 1], cur[i], cur[i + 1]};
                int in = 0, out = 0;
                for (int q = 0; q < 4; q++) {
                    in |= v[q] <= 0.0; /* the one inside convention: f <= iso */
                    out |= v[q] > 0.0;
                }
                crossing += in && out;
            }
        for (size_t i = 0; i <= cx; i++)
            prev[i] = cur[i];
    }
    /* a curve crossing one coarse cell crosses about (fine cells per coarse
     * cell)^(1/2) fine cells, each holding about one vertex */
    double scale = sqrt(((double)nx / (double)cx) * ((double)ny / (double)cy));
    *vertices = (double)crossing * scale;
    return GEOM_OK;
}

/* ------------------------------------------------ the work: cells sampled */

typedef struct blkctx {
    const geom_implicit_field *f;
    const double *bounds;
    size_t nx, ny, B, nbx, nby, wpr;
    double iso, z;
    uint64_t *bits;
    double cells;
    size_t calls;
} blkctx;

/* y of node row j (row 0 is bounds[1] exactly, as marching squares has it) */
static double ycoord(const blkctx *k, size_t j)
{
    return j == 0 ? k->bounds[1] : geom__contour_coord(k->bounds[1], k->bounds[3], k->ny, j);
}

/* Outward by a few ulps: the box then holds every point sampled in it
 * (node coordinates and edge crossings between them) even where rounding
 * made the node coordinates not quite monotonic. */
static double widen(double x, double dir)
{
    return x + dir * (fabs(x) * 8.0 * DBL_EPSILON + DBL_MIN);
}

/* 1: f - iso may vanish (or be NaN) over blocks b0..b1 (x, y), 0: proven not. */
static int may_cross(blkctx *k, const size_t b0[2], const size_t b1[2])
{
    size_t i0 = b0[0] * k->B, i1 = b1[0] * k->B, j0 = b0[1] * k->B, j1 = b1[1] * k->B;
    i1 = i1 < k->nx ? i1 : k->nx;
    j1 = j1 < k->ny ? j1 : k->ny;
    double lo[3] = {widen(geom__contour_coord(k->bounds[0], k->bounds[2], k->nx, i0), -1.0),
                    widen(ycoord(k, j0), -1.0), k->z};
    double hi[3] = {widen(geom__contour_coord(k->bounds[0], k->bounds[2], k->nx, i1), 1.0),
                    widen(ycoord(k, j1), 1.0), k->z};
    double out[2];
    k->calls++;
    if (!k->f->bounds(k->f->user, lo, hi, out) || out[0] != out[0] || out[1] != out[1])
        return 1;
    /* strictly on one side (the one inside convention: f <= iso inside) */
    return !(out[0] - k->iso > 0.0 || out[1] - k->iso < 0.0);
}

/* Quadtree over the blocks (geom__block_split): a box proven on one side
 * is left unset, others are halved along each side longer than one block
 * down to single blocks, which are set. */
static int classify(void *user, const size_t *b0, const size_t *b1, int single)
{
    blkctx *k = user;
    if (!may_cross(k, b0, b1))
        return 0;
    if (single) {
        k->bits[b0[1] * k->wpr + b0[0] / 64] |= (uint64_t)1 << (b0[0] % 64);
        size_t w = (b0[0] + 1) * k->B < k->nx ? k->B : k->nx - b0[0] * k->B;
        size_t h = (b0[1] + 1) * k->B < k->ny ? k->B : k->ny - b0[1] * k->B;
        k->cells += (double)w * (double)h;
    }
    return 1;
}

geom_status geom__contour_blocks(const geom_implicit_field *field, const double bounds[4],
                                 size_t nx, size_t ny, double iso, double z,
                                 const geom_allocator *a, uint64_t **bits, size_t *words_per_row,
                                 size_t *block, double *cells, size_t *calls)
{
    *bits = NULL;
    *words_per_row = 0;
    *block = 0;
    *calls = 0;
    *cells = (double)nx * (double)ny;
    if (!field->bounds)
        return GEOM_OK;
    blkctx k;
    memset(&k, 0, sizeof k);
    k.f = field;
    k.bounds = bounds;
    k.nx = nx;
    k.ny = ny;
    k.iso = iso;
    k.z = z;
    /* blocks of 16 x 16 cells, larger on huge grids (bitmap < 2^27 bytes) */
    for (k.B = 16;; k.B *= 2) {
        k.nbx = (nx + k.B - 1) / k.B;
        k.nby = (ny + k.B - 1) / k.B;
        k.wpr = (k.nbx + 63) / 64;
        if ((double)k.wpr * (double)k.nby * 8.0 < (double)((size_t)1 << 27))
            break;
    }
    k.bits = geom__alloc(a, k.wpr * k.nby * sizeof(uint64_t));
    if (!k.bits)
        return GEOM_ERR_NOMEM;
    memset(k.bits, 0, k.wpr * k.nby * sizeof(uint64_t));
    size_t b0[2] = {0, 0}, b1[2] = {k.nbx, k.nby};
    geom__block_split(2, b0, b1, classify, &k);
    *bits = k.bits;
    *words_per_row = k.wpr;
    *block = k.B;
    *cells = k.cells;
    *calls = k.calls;
    return GEOM_OK;
}

void geom__contour_blocks_free(const geom_allocator *a, uint64_t *bits, size_t words_per_row,
                               size_t rows)
{
    if (bits)
        geom__free(a, bits, words_per_row * rows * sizeof(uint64_t));
}

geom_status geom_implicit_contour_estimate_cells(const geom_implicit_field *field,
                                                 const double bounds[4], size_t nx, size_t ny,
                                                 const geom_implicit_contour_options *opt,
                                                 double *cells)
{
    if (!cells)
        return GEOM_ERR_INVALID_ARG;
    *cells = 0.0;
    double iso = opt ? opt->iso : 0.0, z = opt ? opt->z : 0.0;
    if (check_args(field, bounds, nx, ny, opt) != GEOM_OK)
        return GEOM_ERR_INVALID_ARG;
    if (!field->bounds) {
        *cells = (double)nx * (double)ny;
        return GEOM_OK;
    }
    uint64_t *bits;
    size_t wpr, B, calls;
    const geom_allocator *a = opt ? opt->alloc : NULL;
    geom_status st = geom__contour_blocks(field, bounds, nx, ny, iso, z, a, &bits, &wpr, &B, cells,
                                          &calls);
    if (st == GEOM_OK)
        geom__contour_blocks_free(a, bits, wpr, (ny + B - 1) / B);
    return st;
}
