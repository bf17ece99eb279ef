/*
 * Output size of marching squares before contouring: the field sampled on
 * a coarse grid, its crossing cells counted and scaled to the requested
 * resolution (the iso module's geom_iso_estimate_triangles in 2D).
 */
#include "implicit/implicit_internal.h"

#include <math.h>

/* Coarse cells per axis at most. */
#define COARSE 64

geom_status geom_implicit_contour_estimate(const geom_implicit_field *field,
                                           const double bounds[4], size_t nx, size_t ny,
                                           const geom_implicit_contour_options *opt,
                                           double *vertices)
{
    if (!vertices)
        return GEOM_ERR_INVALID_ARG;
    *vertices = 0.0;
    double iso = opt ? opt->iso : 0.0, z = opt ? opt->z : 0.0;
    if (!field || !field->value || !bounds || nx == 0 || ny == 0 || !isfinite(iso) ||
        !isfinite(z))
        return GEOM_ERR_INVALID_ARG;
    for (int k = 0; k < 4; k++)
        if (!isfinite(bounds[k]))
            return GEOM_ERR_INVALID_ARG;
    if (!(bounds[0] < bounds[2]) || !(bounds[1] < bounds[3]))
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
