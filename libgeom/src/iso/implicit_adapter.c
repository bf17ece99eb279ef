/*
 * Deprecated iso entry points over the implicit module's compiled
 * expressions and sampled volumes: the field and the grid are the implicit
 * module's (geom_implicit_field, geom_implicit_grid), so these only add a
 * status to geom_implicit_field_from_expr / _from_volume /
 * geom_implicit_volume_get_desc.
 */
#include "geom/iso.h"

#include <string.h>

geom_status geom_iso_field_from_expr(const geom_implicit_expr *e, geom_implicit_field *out)
{
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    if (!e)
        return GEOM_ERR_INVALID_ARG;
    geom_implicit_field_from_expr(e, out);
    return GEOM_OK;
}

geom_status geom_iso_field_from_volume(const geom_implicit_volume *v, geom_implicit_field *out)
{
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    if (!v)
        return GEOM_ERR_INVALID_ARG;
    geom_implicit_field_from_volume(v, out);
    return GEOM_OK;
}

geom_status geom_iso_grid_from_volume(const geom_implicit_volume *v, geom_implicit_grid *out)
{
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    if (!v)
        return GEOM_ERR_INVALID_ARG;
    geom_implicit_volume_get_desc(v, out);
    return GEOM_OK;
}
