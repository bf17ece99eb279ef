/*
 * The one trilinear interpolator of the library (and its interpolated
 * central-difference gradient) over borrowed samples: sampled volumes
 * (geom_implicit_volume_eval) and marching cubes' grids
 * (geom_iso_grid_value) both call it, so they agree bit for bit.
 */
#include "implicit/implicit_internal.h"

#include <math.h>

static inline double spacing_of(const geom_implicit_grid *d, int a)
{
    return d->spacing[a] > 0 ? d->spacing[a] : 1.0;
}

static inline double at(const geom_implicit_grid *d, const void *data, size_t idx)
{
    if (d->type == GEOM_IMPLICIT_SCALAR_F32)
        return (double)((const float *)data)[idx];
    return ((const double *)data)[idx];
}

/* Cell index and fraction along axis a for coordinate c (clamped). */
static void locate(const geom_implicit_grid *d, int a, double c, size_t *i0, double *f)
{
    size_t n = d->dims[a];
    if (n < 2) {
        *i0 = 0;
        *f = 0.0;
        return;
    }
    double u = (c - d->origin[a]) / spacing_of(d, a);
    double umax = (double)(n - 1);
    if (!(u > 0.0))
        u = 0.0;
    if (u > umax)
        u = umax;
    double fl = floor(u);
    if (fl >= umax)
        fl = umax - 1.0;
    *i0 = (size_t)fl;
    *f = u - fl;
}

/* (1 - t) a + t b, exactly a at t = 0 and b at t = 1 (the other end is not
 * read then, so a NaN neighbour does not leak into a sample's value). */
static inline double lerp(double a, double b, double t)
{
    if (t == 0.0)
        return a;
    if (t == 1.0)
        return b;
    return (1.0 - t) * a + t * b;
}

double geom_implicit_samples_value(const geom_implicit_grid *d, const void *data,
                                   const double p[3])
{
    if (d && !data)
        data = d->data;
    if (!d || !data || !p || isnan(p[0]) || isnan(p[1]) || isnan(p[2]))
        return NAN;
    size_t i0[3];
    double t[3];
    for (int a = 0; a < 3; a++)
        locate(d, a, p[a], &i0[a], &t[a]);
    size_t nx = d->dims[0], ny = d->dims[1];
    size_t di = nx > 1, dj = ny > 1 ? nx : 0, dk = d->dims[2] > 1 ? nx * ny : 0;
    size_t b = i0[0] + nx * (i0[1] + ny * i0[2]);
    double x[4];
    for (int q = 0; q < 4; q++) {
        size_t r = b + ((q & 1) ? dj : 0) + ((q & 2) ? dk : 0);
        x[q] = t[0] == 1.0 ? at(d, data, r + di)
                           : t[0] == 0.0 ? at(d, data, r)
                                         : lerp(at(d, data, r), at(d, data, r + di), t[0]);
    }
    double y0 = lerp(x[0], x[1], t[1]), y1 = lerp(x[2], x[3], t[1]);
    return lerp(y0, y1, t[2]);
}

/* Central difference of the samples at (i, j, k) along axis a: one-sided
 * on the border, 0 along an axis with one sample. */
static double node_diff(const geom_implicit_grid *d, const void *data, const size_t ijk[3],
                        int a)
{
    size_t n = d->dims[a];
    if (n < 2)
        return 0.0;
    size_t stride = a == 0 ? 1 : a == 1 ? d->dims[0] : d->dims[0] * d->dims[1];
    size_t idx = ijk[0] + d->dims[0] * (ijk[1] + d->dims[1] * ijk[2]);
    size_t i = ijk[a];
    double sp = spacing_of(d, a);
    if (i == 0)
        return (at(d, data, idx + stride) - at(d, data, idx)) / sp;
    if (i == n - 1)
        return (at(d, data, idx) - at(d, data, idx - stride)) / sp;
    return (at(d, data, idx + stride) - at(d, data, idx - stride)) / (2.0 * sp);
}

void geom_implicit_samples_gradient(const geom_implicit_grid *d, const void *data,
                                    const double p[3], double grad[3])
{
    if (!grad)
        return;
    grad[0] = grad[1] = grad[2] = NAN;
    if (d && !data)
        data = d->data;
    if (!d || !data || !p || isnan(p[0]) || isnan(p[1]) || isnan(p[2]))
        return;
    size_t i0[3];
    double f[3];
    for (int a = 0; a < 3; a++)
        locate(d, a, p[a], &i0[a], &f[a]);
    double g[3] = {0.0, 0.0, 0.0};
    for (int corner = 0; corner < 8; corner++) {
        double w = ((corner & 1) ? f[0] : 1.0 - f[0]) * ((corner & 2) ? f[1] : 1.0 - f[1]) *
                   ((corner & 4) ? f[2] : 1.0 - f[2]);
        if (w == 0.0)
            continue;
        size_t ijk[3] = {i0[0] + (size_t)((corner & 1) && d->dims[0] > 1),
                         i0[1] + (size_t)((corner & 2) && d->dims[1] > 1),
                         i0[2] + (size_t)((corner & 4) && d->dims[2] > 1)};
        for (int a = 0; a < 3; a++)
            g[a] += w * node_diff(d, data, ijk, a);
    }
    grad[0] = g[0];
    grad[1] = g[1];
    grad[2] = g[2];
}

/* ------------------------------------------------------------------ batch */


/* Lanes per block of the batch interpolator. */
#define TRI_BLOCK GEOM__TRI_BLOCK

/* lerp() of TRI_BLOCK lanes: out = (1 - t) a + t b, exactly a at t = 0 and
 * b at t = 1. */
GEOM__CLONE_INLINE void lerp_lanes(const double *restrict a, const double *restrict b,
                              const double *restrict t, double *restrict out)
{
    for (int l = 0; l < TRI_BLOCK; l++) {
        double m = (1.0 - t[l]) * a[l] + t[l] * b[l];
        out[l] = t[l] == 0.0 ? a[l] : t[l] == 1.0 ? b[l] : m;
    }
}

/* TRI_BLOCK points p (3 doubles each) of a grid with every dims >= 2 and
 * below 2^31: gathered into lanes, located, the 8 corner samples loaded,
 * then interpolated lane by lane without branches (the loops the compiler
 * vectorises), each lane doing exactly geom_implicit_samples_value's
 * operations; samples of type T. */
#define TRI_VALUES_BLOCK(name, T)                                                              \
    GEOM__CLONE_INLINE void name(const double *o, const double *s, const double *um, int64_t nx,   \
                            int64_t nxy, const T *restrict S, const double *restrict p,       \
                            double *restrict out)                                              \
    {                                                                                          \
        double c[3][TRI_BLOCK], t[3][TRI_BLOCK], v[8][TRI_BLOCK], w[4][TRI_BLOCK];             \
        int32_t i0[3][TRI_BLOCK];                                                              \
        int64_t b[TRI_BLOCK];                                                                  \
        for (int l = 0; l < TRI_BLOCK; l++) {                                                  \
            c[0][l] = p[3 * l];                                                                \
            c[1][l] = p[3 * l + 1];                                                            \
            c[2][l] = p[3 * l + 2];                                                            \
        }                                                                                      \
        geom__locate_lanes(c[0], o[0], s[0], um[0], i0[0], t[0]);                                    \
        geom__locate_lanes(c[1], o[1], s[1], um[1], i0[1], t[1]);                                    \
        geom__locate_lanes(c[2], o[2], s[2], um[2], i0[2], t[2]);                                    \
        for (int l = 0; l < TRI_BLOCK; l++)                                                    \
            b[l] = (int64_t)i0[0][l] + nx * (int64_t)i0[1][l] + nxy * (int64_t)i0[2][l];       \
        for (int l = 0; l < TRI_BLOCK; l++) {                                                  \
            const T *q = S + b[l];                                                             \
            v[0][l] = (double)q[0];                                                            \
            v[1][l] = (double)q[1];                                                            \
            v[2][l] = (double)q[nx];                                                           \
            v[3][l] = (double)q[nx + 1];                                                       \
            v[4][l] = (double)q[nxy];                                                          \
            v[5][l] = (double)q[nxy + 1];                                                      \
            v[6][l] = (double)q[nxy + nx];                                                     \
            v[7][l] = (double)q[nxy + nx + 1];                                                 \
        }                                                                                      \
        for (int k = 0; k < 4; k++)                                                            \
            lerp_lanes(v[2 * k], v[2 * k + 1], t[0], w[k]);                                    \
        lerp_lanes(w[0], w[1], t[1], v[0]);                                                    \
        lerp_lanes(w[2], w[3], t[1], v[1]);                                                    \
        lerp_lanes(v[0], v[1], t[2], v[2]);                                                    \
        for (int l = 0; l < TRI_BLOCK; l++)                                                    \
            out[l] = isnan(c[0][l]) | isnan(c[1][l]) | isnan(c[2][l]) ? NAN : v[2][l];         \
    }
TRI_VALUES_BLOCK(values_block_f32, float)
TRI_VALUES_BLOCK(values_block_f64, double)

GEOM_SIMD_CLONES
static void values_blocks(const geom_implicit_grid *d, const void *data, size_t nb,
                          const double *p, double *out)
{
    double s[3], um[3];
    for (int a = 0; a < 3; a++) {
        s[a] = spacing_of(d, a);
        um[a] = (double)(d->dims[a] - 1);
    }
    int64_t nx = (int64_t)d->dims[0], nxy = nx * (int64_t)d->dims[1];
    if (d->type == GEOM_IMPLICIT_SCALAR_F32)
        for (size_t i = 0; i < nb; i++)
            values_block_f32(d->origin, s, um, nx, nxy, (const float *)data, p + 3 * TRI_BLOCK * i,
                         out + TRI_BLOCK * i);
    else
        for (size_t i = 0; i < nb; i++)
            values_block_f64(d->origin, s, um, nx, nxy, (const double *)data, p + 3 * TRI_BLOCK * i,
                         out + TRI_BLOCK * i);
}

void geom__implicit_samples_values(const geom_implicit_grid *d, size_t n, const double *p,
                                   double *out)
{
    size_t done = 0;
    if (d && d->data && p) {
        int fast = d->type == GEOM_IMPLICIT_SCALAR_F32 || d->type == GEOM_IMPLICIT_SCALAR_F64;
        for (int a = 0; a < 3; a++)
            fast &= d->dims[a] >= 2 && d->dims[a] <= INT32_MAX;
        if (fast) {
            done = n / TRI_BLOCK * TRI_BLOCK;
            values_blocks(d, d->data, n / TRI_BLOCK, p, out);
        }
    }
    for (size_t i = done; i < n; i++)
        out[i] = p ? geom_implicit_samples_value(d, NULL, p + 3 * i) : NAN;
}
