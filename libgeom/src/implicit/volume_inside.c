/*
 * Which side of the isovalue is a sampled volume's inside: the samples on
 * the grid's six faces are taken to be outside. A CT or MRI volume (dense
 * inside, air around) has its boundary samples below iso, so its inside is
 * f >= iso; a distance field (negative inside) has them above.
 */
#include "implicit/implicit_internal.h"

geom_status geom_implicit_volume_detect_inside(const geom_implicit_volume *v, double iso, int *above,
                                               size_t *below, size_t *total)
{
    geom_implicit_grid d;
    size_t nb = 0, nt = 0;
    if (!v || isnan(iso))
        return GEOM_ERR_INVALID_ARG;
    geom_implicit_volume_get_desc(v, &d);
    const void *data = geom_implicit_volume_cdata(v);
    size_t nx = d.dims[0], ny = d.dims[1], nz = d.dims[2];
    for (size_t k = 0; k < nz; k++)
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++) {
                if (!(i == 0 || j == 0 || k == 0 || i + 1 == nx || j + 1 == ny || k + 1 == nz)) {
                    i = nx - 2; /* jump to the last column of this row */
                    continue;
                }
                size_t at = i + nx * (j + ny * k);
                double s = d.type == GEOM_IMPLICIT_SCALAR_F32 ? (double)((const float *)data)[at]
                                                              : ((const double *)data)[at];
                nt++;
                if (s < iso)
                    nb++;
            }
    if (above)
        *above = 2 * nb > nt;
    if (below)
        *below = nb;
    if (total)
        *total = nt;
    return GEOM_OK;
}
