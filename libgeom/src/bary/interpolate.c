/* Attribute interpolation with barycentric (or generalized) weights. */
#include "bary/bary_internal.h"

geom_status geom_bary_interpolate(size_t k, const double *l, size_t ncomp, const double *attr,
                                  double *out)
{
    if (!l || !attr || !out || k == 0)
        return GEOM_ERR_INVALID_ARG;
    for (size_t j = 0; j < ncomp; j++) {
        double s = 0.0;
        for (size_t i = 0; i < k; i++)
            s += l[i] * attr[i * ncomp + j];
        out[j] = s;
    }
    return GEOM_OK;
}
