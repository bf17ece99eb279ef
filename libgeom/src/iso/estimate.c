/*
 * Output size of an isosurface before extracting it: the field sampled on a
 * coarse grid (a sampled grid: every cell), its crossing cells counted and
 * scaled to the requested resolution.
 */
#include "iso/iso_internal.h"

#include <math.h>
#include <stdlib.h>

/* Marching cubes makes about two triangles per cell the surface crosses. */
#define TRIS_PER_CELL 2.0

geom_status geom_iso_estimate_triangles(const geom_iso_field *f, const double bounds[6],
                                        const size_t res[3], double iso, double *triangles)
{
    if (!triangles)
        return GEOM_ERR_INVALID_ARG;
    *triangles = 0.0;
    if (!f || !f->value || !bounds || !res || !isfinite(iso))
        return GEOM_ERR_INVALID_ARG;
    size_t c[3];
    double scale = 1.0;
    for (int a = 0; a < 3; a++) {
        if (res[a] == 0 || !(bounds[a] < bounds[a + 3]))
            return GEOM_ERR_INVALID_ARG;
        c[a] = res[a] < 40 ? res[a] : 40;
        scale *= (double)res[a] / (double)c[a];
    }
    /* a surface piece crossing one coarse cell crosses about
     * (fine cells per coarse cell)^(2/3) fine cells */
    scale = pow(scale, 2.0 / 3.0);
    size_t nx = c[0] + 1, ny = c[1] + 1, nz = c[2] + 1;
    double *val = malloc(nx * ny * 2 * sizeof *val);
    if (!val)
        return GEOM_ERR_NOMEM;
    size_t crossing = 0;
    for (size_t k = 0; k < nz; k++) {
        double *cur = val + (k & 1) * nx * ny, *prev = val + ((k + 1) & 1) * nx * ny;
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++) {
                double p[3] = {bounds[0] + (bounds[3] - bounds[0]) * (double)i / (double)c[0],
                               bounds[1] + (bounds[4] - bounds[1]) * (double)j / (double)c[1],
                               bounds[2] + (bounds[5] - bounds[2]) * (double)k / (double)c[2]};
                cur[i + nx * j] = f->value(f->user, p) - iso;
            }
        if (k == 0)
            continue;
        for (size_t j = 0; j + 1 < ny; j++)
            for (size_t i = 0; i + 1 < nx; i++) {
                int below = 0, above = 0;
                for (int q = 0; q < 8; q++) {
                    const double *layer = (q & 4) ? cur : prev;
                    double v = layer[i + (q & 1) + nx * (j + ((q >> 1) & 1))];
                    below |= v <= 0.0;
                    above |= v > 0.0;
                }
                crossing += below && above;
            }
    }
    free(val);
    *triangles = TRIS_PER_CELL * (double)crossing * scale;
    return GEOM_OK;
}

geom_status geom_iso_grid_estimate_triangles(const geom_iso_grid *g, double iso,
                                             double *triangles)
{
    if (!triangles)
        return GEOM_ERR_INVALID_ARG;
    *triangles = 0.0;
    geom_status st = geom_iso_grid_check(g);
    if (st != GEOM_OK)
        return st;
    if (!isfinite(iso))
        return GEOM_ERR_INVALID_ARG;
    size_t nx = g->dims[0], ny = g->dims[1], nz = g->dims[2];
    const float *f32 = g->type == GEOM_ISO_SCALAR_F32 ? g->data : NULL;
    const double *f64 = g->type == GEOM_ISO_SCALAR_F64 ? g->data : NULL;
    size_t crossing = 0;
    for (size_t k = 0; k + 1 < nz; k++)
        for (size_t j = 0; j + 1 < ny; j++)
            for (size_t i = 0; i + 1 < nx; i++) {
                int below = 0, above = 0;
                for (int q = 0; q < 8; q++) {
                    size_t idx = (i + (q & 1)) + nx * ((j + ((q >> 1) & 1)) + ny * (k + (q >> 2)));
                    double v = (f32 ? (double)f32[idx] : f64[idx]) - iso;
                    below |= v <= 0.0;
                    above |= v > 0.0;
                }
                crossing += below && above;
            }
    *triangles = TRIS_PER_CELL * (double)crossing;
    return GEOM_OK;
}
