/* A dense sampled grid as a field: trilinear values, interpolated
 * central-difference gradients. */
#include "iso/iso_internal.h"

#include <string.h>

geom_status geom_iso_grid_check(const geom_implicit_grid *g)
{
    if (!g || !g->data)
        return GEOM_ERR_INVALID_ARG;
    if (g->type != GEOM_ISO_SCALAR_F32 && g->type != GEOM_ISO_SCALAR_F64)
        return GEOM_ERR_INVALID_ARG;
    size_t n = 1;
    for (int a = 0; a < 3; a++) {
        if (g->dims[a] == 0)
            return GEOM_ERR_INVALID_ARG;
        if (!(g->spacing[a] >= 0) || !isfinite(g->spacing[a]) || !isfinite(g->origin[a]))
            return GEOM_ERR_INVALID_ARG;
        if (geom__size_mul(n, g->dims[a], &n) != GEOM_OK)
            return GEOM_ERR_LIMIT;
    }
    size_t bytes;
    if (geom__size_mul(n, g->type == GEOM_ISO_SCALAR_F32 ? sizeof(float) : sizeof(double),
                      &bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    return GEOM_OK;
}

/* The implicit module's interpolator: one for the whole library (the grid
 * is the implicit module's geom_implicit_grid). */
double geom_iso_grid_value(const geom_implicit_grid *g, const double p[3])
{
    return geom_implicit_samples_value(g, g->data, p);
}

void geom_iso_grid_gradient(const geom_implicit_grid *g, const double p[3], double grad[3])
{
    geom_implicit_samples_gradient(g, g->data, p, grad);
}

double geom_iso_grid_value_cb(void *user, const double p[3])
{
    return geom_iso_grid_value((const geom_implicit_grid *)user, p);
}

double geom_iso_grid_gradient_cb(void *user, const double p[3], double grad[3])
{
    const geom_implicit_grid *g = user;
    geom_implicit_samples_gradient(g, g->data, p, grad);
    return geom_implicit_samples_value(g, g->data, p);
}

geom_status geom_iso_field_from_grid(const geom_implicit_grid *g, geom_implicit_field *out)
{
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    geom_status st = geom_iso_grid_check(g);
    if (st != GEOM_OK)
        return st;
    out->value = geom_iso_grid_value_cb;
    out->gradient = geom_iso_grid_gradient_cb;
    out->user = (void *)(uintptr_t)g;
    return GEOM_OK;
}
