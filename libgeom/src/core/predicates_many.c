/*
 * The exact predicates over arrays (geom_predicate_many): one call over n
 * rows, each argument one point per row or the same point for every row
 * (stride 0), so bindings pay the call overhead once. Every row is the
 * single-point predicate's own evaluation (same filter, same exact
 * fallback), so the results are bitwise those of the single functions;
 * orient2d and orient3d run their filters over blocks of rows without
 * branches (geom__orient2d_many, geom__orient3d_many in predicates.c).
 */
#include "core/internal.h"

geom_status geom_predicate_many(geom_predicate kind, size_t n, const double *const pts[4],
                                const size_t strides[4], double *out)
{
    if (n == 0)
        return GEOM_OK;
    if (!pts || !strides || !out)
        return GEOM_ERR_INVALID_ARG;
    int np;
    switch (kind) {
    case GEOM_PREDICATE_ORIENT2D:
    case GEOM_PREDICATE_ORIENT2D_EXACT:
        np = 3;
        break;
    case GEOM_PREDICATE_ORIENT3D:
    case GEOM_PREDICATE_INCIRCLE:
    case GEOM_PREDICATE_ORIENT3D_EXACT:
        np = 4;
        break;
    default:
        return GEOM_ERR_INVALID_ARG;
    }
    for (int j = 0; j < np; j++)
        if (!pts[j])
            return GEOM_ERR_INVALID_ARG;
    const double *a = pts[0], *b = pts[1], *c = pts[2], *d = np == 4 ? pts[3] : NULL;
    size_t sa = strides[0], sb = strides[1], sc = strides[2], sd = np == 4 ? strides[3] : 0;
    switch (kind) {
    case GEOM_PREDICATE_ORIENT2D:
        geom__orient2d_many(n, a, sa, b, sb, c, sc, out);
        break;
    case GEOM_PREDICATE_ORIENT2D_EXACT:
        for (size_t i = 0; i < n; i++)
            out[i] = geom_orient2d_exact(a + i * sa, b + i * sb, c + i * sc);
        break;
    case GEOM_PREDICATE_ORIENT3D:
        geom__orient3d_many(n, a, sa, b, sb, c, sc, d, sd, out);
        break;
    case GEOM_PREDICATE_INCIRCLE:
        for (size_t i = 0; i < n; i++)
            out[i] = geom_incircle(a + i * sa, b + i * sb, c + i * sc, d + i * sd);
        break;
    default: /* GEOM_PREDICATE_ORIENT3D_EXACT (kind checked above) */
        for (size_t i = 0; i < n; i++)
            out[i] = geom_orient3d_exact(a + i * sa, b + i * sb, c + i * sc, d + i * sd);
        break;
    }
    return GEOM_OK;
}
