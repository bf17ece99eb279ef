/*
 * Fields and grids for marching cubes from the implicit module's compiled
 * expressions and sampled volumes. Kept in its own object file: a program
 * that extracts isosurfaces of its own callbacks does not link it.
 */
#include "geom/iso.h"

#include <stdint.h>

#include <math.h>
#include <string.h>

static void expr_gradient(void *user, const double p[3], double g[3])
{
    geom_implicit_expr_eval_grad((const geom_implicit_expr *)user, p, g);
}

static void expr_values(void *user, size_t n, const double *p, double *out)
{
    geom_implicit_expr_eval_many((const geom_implicit_expr *)user, n, p, out);
}

static void expr_gradients(void *user, size_t n, const double *p, double *values, double *grads)
{
    geom_implicit_expr_eval_grad_many((const geom_implicit_expr *)user, n, p, values, grads);
}

static int expr_bounds(void *user, const double lo[3], const double hi[3], double out[2])
{
    int defined = 0;
    if (geom_implicit_expr_eval_bounds((const geom_implicit_expr *)user, lo, hi, out, &defined) !=
        GEOM_OK)
        return 0;
    return defined && !isnan(out[0]) && !isnan(out[1]);
}

geom_status geom_iso_field_from_expr(const geom_implicit_expr *e,
                                            geom_iso_field *out)
{
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    if (!e)
        return GEOM_ERR_INVALID_ARG;
    out->value = geom_implicit_expr_value_cb;
    out->gradient = expr_gradient;
    out->values = expr_values;
    out->gradients = expr_gradients;
    out->bounds = expr_bounds;
    out->user = (void *)(uintptr_t)e;
    out->exact = 1;
    return GEOM_OK;
}

static void volume_gradient(void *user, const double p[3], double g[3])
{
    geom_implicit_volume_eval_grad((const geom_implicit_volume *)user, p, g);
}

geom_status geom_iso_field_from_volume(const geom_implicit_volume *v,
                                              geom_iso_field *out)
{
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    if (!v)
        return GEOM_ERR_INVALID_ARG;
    out->value = geom_implicit_volume_value_cb;
    out->gradient = volume_gradient;
    out->user = (void *)(uintptr_t)v;
    out->exact = 0;
    return GEOM_OK;
}

geom_status geom_iso_grid_from_volume(const geom_implicit_volume *v,
                                             geom_iso_grid *out)
{
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    if (!v)
        return GEOM_ERR_INVALID_ARG;
    geom_implicit_volume_desc d;
    geom_implicit_volume_get_desc(v, &d);
    for (int a = 0; a < 3; a++) {
        out->dims[a] = d.dims[a];
        out->spacing[a] = d.spacing[a];
        out->origin[a] = d.origin[a];
    }
    out->type = d.type == GEOM_IMPLICIT_SCALAR_F32 ? GEOM_ISO_SCALAR_F32 : GEOM_ISO_SCALAR_F64;
    out->data = geom_implicit_volume_cdata(v);
    return GEOM_OK;
}
