/* A dense sampled grid as a field: trilinear values, interpolated
 * central-difference gradients. */
#include "iso/iso_internal.h"

#include <string.h>

geom_status geom_iso_grid_check(const geom_iso_grid *g)
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

static void desc_of(const geom_iso_grid *g, geom_implicit_volume_desc *d)
{
    memset(d, 0, sizeof *d);
    for (int a = 0; a < 3; a++) {
        d->dims[a] = g->dims[a];
        d->spacing[a] = g->spacing[a];
        d->origin[a] = g->origin[a];
    }
    d->type = g->type == GEOM_ISO_SCALAR_F32 ? GEOM_IMPLICIT_SCALAR_F32 : GEOM_IMPLICIT_SCALAR_F64;
}

/* The implicit module's interpolator: one for the whole library. */
double geom_iso_grid_value(const geom_iso_grid *g, const double p[3])
{
    geom_implicit_volume_desc d;
    desc_of(g, &d);
    return geom_implicit_samples_value(&d, g->data, p);
}

void geom_iso_grid_gradient(const geom_iso_grid *g, const double p[3], double grad[3])
{
    geom_implicit_volume_desc d;
    desc_of(g, &d);
    geom_implicit_samples_gradient(&d, g->data, p, grad);
}

double geom_iso_grid_value_cb(void *user, const double p[3])
{
    return geom_iso_grid_value((const geom_iso_grid *)user, p);
}

void geom_iso_grid_gradient_cb(void *user, const double p[3], double grad[3])
{
    geom_iso_grid_gradient((const geom_iso_grid *)user, p, grad);
}

geom_status geom_iso_field_from_grid(const geom_iso_grid *g, geom_iso_field *out)
{
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    out->value = NULL;
    out->gradient = NULL;
    out->values = NULL;
    out->user = NULL;
    out->exact = 0;
    geom_status st = geom_iso_grid_check(g);
    if (st != GEOM_OK)
        return st;
    out->value = geom_iso_grid_value_cb;
    out->gradient = geom_iso_grid_gradient_cb;
    out->user = (void *)(uintptr_t)g;
    return GEOM_OK;
}
