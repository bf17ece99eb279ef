/* A dense sampled grid as a field: trilinear values, interpolated
 * central-difference gradients. */
#include "iso/iso_internal.h"

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
        if (geom_size_mul(n, g->dims[a], &n) != GEOM_OK)
            return GEOM_ERR_LIMIT;
    }
    size_t bytes;
    if (geom_size_mul(n, g->type == GEOM_ISO_SCALAR_F32 ? sizeof(float) : sizeof(double),
                      &bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    return GEOM_OK;
}

static double spacing_of(const geom_iso_grid *g, int a)
{
    return g->spacing[a] > 0 ? g->spacing[a] : 1.0;
}

/* Cell index and fraction along axis a for coordinate x (clamped). */
static void locate(const geom_iso_grid *g, int a, double x, size_t *i, double *t)
{
    size_t n = g->dims[a];
    if (n < 2) {
        *i = 0;
        *t = 0;
        return;
    }
    double u = (x - g->origin[a]) / spacing_of(g, a);
    double top = (double)(n - 1);
    if (!(u > 0))
        u = 0;
    if (u > top)
        u = top;
    double fl = floor(u);
    size_t k = (size_t)fl;
    if (k >= n - 1)
        k = n - 2;
    *i = k;
    *t = u - (double)k;
}

double geom_iso_grid_value(const geom_iso_grid *g, const double p[3])
{
    if (isnan(p[0]) || isnan(p[1]) || isnan(p[2]))
        return NAN;
    size_t i[3];
    double t[3];
    for (int a = 0; a < 3; a++)
        locate(g, a, p[a], &i[a], &t[a]);
    size_t i1 = g->dims[0] > 1 ? i[0] + 1 : i[0];
    size_t j1 = g->dims[1] > 1 ? i[1] + 1 : i[1];
    size_t k1 = g->dims[2] > 1 ? i[2] + 1 : i[2];
    double c000 = iso_grid_at(g, i[0], i[1], i[2]), c100 = iso_grid_at(g, i1, i[1], i[2]);
    double c010 = iso_grid_at(g, i[0], j1, i[2]), c110 = iso_grid_at(g, i1, j1, i[2]);
    double c001 = iso_grid_at(g, i[0], i[1], k1), c101 = iso_grid_at(g, i1, i[1], k1);
    double c011 = iso_grid_at(g, i[0], j1, k1), c111 = iso_grid_at(g, i1, j1, k1);
    /* (1 - t) a + t b is exact at t = 0 and t = 1. */
    double x00 = (1 - t[0]) * c000 + t[0] * c100, x10 = (1 - t[0]) * c010 + t[0] * c110;
    double x01 = (1 - t[0]) * c001 + t[0] * c101, x11 = (1 - t[0]) * c011 + t[0] * c111;
    double y0 = (1 - t[1]) * x00 + t[1] * x10, y1 = (1 - t[1]) * x01 + t[1] * x11;
    return (1 - t[2]) * y0 + t[2] * y1;
}

/* Central difference of the samples at (i, j, k) along axis a. */
static double sample_diff(const geom_iso_grid *g, size_t i, size_t j, size_t k, int a)
{
    size_t idx[3] = {i, j, k};
    size_t n = g->dims[a];
    if (n < 2)
        return 0.0;
    size_t lo[3] = {i, j, k}, hi[3] = {i, j, k};
    if (idx[a] > 0)
        lo[a] = idx[a] - 1;
    if (idx[a] + 1 < n)
        hi[a] = idx[a] + 1;
    double d = (double)(hi[a] - lo[a]) * spacing_of(g, a);
    return (iso_grid_at(g, hi[0], hi[1], hi[2]) - iso_grid_at(g, lo[0], lo[1], lo[2])) / d;
}

void geom_iso_grid_gradient(const geom_iso_grid *g, const double p[3], double grad[3])
{
    if (isnan(p[0]) || isnan(p[1]) || isnan(p[2])) {
        grad[0] = grad[1] = grad[2] = NAN;
        return;
    }
    size_t i[3];
    double t[3];
    for (int a = 0; a < 3; a++)
        locate(g, a, p[a], &i[a], &t[a]);
    for (int a = 0; a < 3; a++) {
        double acc = 0;
        for (int c = 0; c < 8; c++) {
            int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
            double w = (dx ? t[0] : 1 - t[0]) * (dy ? t[1] : 1 - t[1]) * (dz ? t[2] : 1 - t[2]);
            if (w == 0)
                continue;
            size_t ii = i[0] + (size_t)(dx && g->dims[0] > 1);
            size_t jj = i[1] + (size_t)(dy && g->dims[1] > 1);
            size_t kk = i[2] + (size_t)(dz && g->dims[2] > 1);
            acc += w * sample_diff(g, ii, jj, kk, a);
        }
        grad[a] = acc;
    }
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
