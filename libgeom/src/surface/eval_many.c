/* Batch evaluation of a surface over arrays of parameters (for bindings). */
#include "surface/surface_internal.h"

#include <math.h>

geom_status geom_surface_eval_many(const geom_nurbs_surface *s, size_t n, const double *uv,
                                   unsigned flags, int normals, double *out, int32_t *status,
                                   size_t *n_failed)
{
    if (n_failed)
        *n_failed = 0;
    if (n == 0)
        return GEOM_OK;
    if (!s || !uv || !out)
        return GEOM_ERR_INVALID_ARG;
    size_t failed = 0;
    for (size_t i = 0; i < n; i++) {
        double *o = out + 3 * i;
        geom_status st = normals ? geom_surface_normal(s, uv[2 * i], uv[2 * i + 1], flags, o, NULL)
                                 : geom_surface_eval(s, uv[2 * i], uv[2 * i + 1], flags, o);
        if (st != GEOM_OK) {
            o[0] = o[1] = o[2] = NAN;
            failed++;
        }
        if (status)
            status[i] = (int32_t)st;
    }
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}
