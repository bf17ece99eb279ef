/* Batch trilinear evaluation of a volume over an array of points. */
#include "implicit/implicit_internal.h"

void geom_implicit_volume_eval_many(const geom_implicit_volume *v, size_t n, const double *p,
                                    double *out, double *grad)
{
    if (!out)
        return;
    if (v && p && !grad) { /* values only: the block interpolator (trilinear.c) */
        geom_implicit_grid g;
        geom_implicit_volume_get_desc(v, &g);
        geom__implicit_samples_values(&g, n, p, out);
        return;
    }
    for (size_t i = 0; i < n; i++)
        out[i] = !v || !p ? NAN
                 : grad  ? geom_implicit_volume_eval_grad(v, p + 3 * i, grad + 3 * i)
                         : geom_implicit_volume_eval(v, p + 3 * i);
}
