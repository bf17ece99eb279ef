/* Batch trilinear evaluation of a volume (values and gradients) over an
 * array of points. */
#include "implicit/implicit_internal.h"

#include <math.h>

#define GB GEOM__TRI_BLOCK

/* geom_implicit_samples_gradient at GB points p (3 doubles each) of a grid
 * with every dims in [2, 2^31) into grad (3 doubles each): gathered into
 * lanes and located as the values are (geom__locate_lanes); the 8 corner
 * samples of each lane's cell loaded once; then for each corner in order
 * and each axis, the corner's weight times the central difference there
 * added lane by lane without branches (a zero weight adds nothing, as the
 * single-point function skips the corner). One end of each difference is
 * the neighbouring corner of the cell, the other the one sample outside
 * the cell along that axis (the node itself on the border, where the
 * difference is one-sided), so a lane loads 32 samples, not 48 pairs.
 * Every lane does exactly the single-point function's operations in its
 * order; samples of type T. */
#define GRAD_BLOCK(name, T)                                                                    \
    GEOM__CLONE_INLINE void name(const double *o, const double *s, const double *inv,        \
                                 const double *um, const int64_t *stride,                     \
                                 const T *restrict S,                                         \
                                 const double *restrict p, double *restrict grad)             \
    {                                                                                          \
        double c[3][GB], f[3][GB], g[3][GB], w[GB], V[8][GB], x[GB];                           \
        int32_t i0[3][GB];                                                                     \
        int64_t b[GB], off[8];                                                                 \
        for (int l = 0; l < GB; l++) {                                                         \
            c[0][l] = p[3 * l];                                                                \
            c[1][l] = p[3 * l + 1];                                                            \
            c[2][l] = p[3 * l + 2];                                                            \
        }                                                                                      \
        for (int a = 0; a < 3; a++)                                                            \
            geom__locate_lanes(c[a], o[a], s[a], um[a], i0[a], f[a]);                          \
        for (int l = 0; l < GB; l++)                                                           \
            b[l] = (int64_t)i0[0][l] + stride[1] * (int64_t)i0[1][l] +                         \
                   stride[2] * (int64_t)i0[2][l];                                              \
        for (int corner = 0; corner < 8; corner++) {                                           \
            off[corner] = (corner & 1) + ((corner & 2) ? stride[1] : 0) +                      \
                          ((corner & 4) ? stride[2] : 0);                                      \
            for (int l = 0; l < GB; l++)                                                       \
                V[corner][l] = (double)S[b[l] + off[corner]];                                  \
        }                                                                                      \
        for (int a = 0; a < 3; a++)                                                            \
            for (int l = 0; l < GB; l++)                                                       \
                g[a][l] = 0.0;                                                                 \
        for (int corner = 0; corner < 8; corner++) {                                           \
            int bx = corner & 1, by = (corner >> 1) & 1, bz = (corner >> 2) & 1;               \
            for (int l = 0; l < GB; l++)                                                       \
                w[l] = (bx ? f[0][l] : 1.0 - f[0][l]) * (by ? f[1][l] : 1.0 - f[1][l]) *       \
                       (bz ? f[2][l] : 1.0 - f[2][l]);                                         \
            for (int a = 0; a < 3; a++) {                                                      \
                int bit = (corner >> a) & 1;                                                   \
                int64_t edge = bit ? (int64_t)um[a] : 0, out = bit ? stride[a] : -stride[a];   \
                const double *nb = V[corner ^ (1 << a)];                                       \
                double sp = s[a], sp2 = 2.0 * s[a];                                            \
                const int32_t *ia = i0[a];                                                     \
                double *ga = g[a];                                                             \
                int64_t oc = off[corner], e0 = edge - bit;                                     \
                for (int l = 0; l < GB; l++) /* the gathers: their own loop */                 \
                    x[l] = (double)S[b[l] + oc + (ia[l] == e0 ? 0 : out)];                     \
                for (int l = 0; l < GB; l++) /* the difference, upper minus lower */           \
                    x[l] = bit ? x[l] - nb[l] : nb[l] - x[l];                                  \
                if (inv[a] > 0.0) /* x / 2^k is x * 2^-k: the same bits */                     \
                    for (int l = 0; l < GB; l++) {                                             \
                        double dd = x[l] * (ia[l] == e0 ? inv[a] : 0.5 * inv[a]);              \
                        double sum = ga[l] + w[l] * dd; /* computed either way */              \
                        ga[l] = w[l] == 0.0 ? ga[l] : sum;                                     \
                    }                                                                          \
                else                                                                           \
                    for (int l = 0; l < GB; l++) {                                             \
                        double dd = x[l] / (ia[l] == e0 ? sp : sp2);                           \
                        double sum = ga[l] + w[l] * dd;                                        \
                        ga[l] = w[l] == 0.0 ? ga[l] : sum;                                     \
                    }                                                                          \
            }                                                                                  \
        }                                                                                      \
        for (int l = 0; l < GB; l++) {                                                         \
            int nan = isnan(c[0][l]) | isnan(c[1][l]) | isnan(c[2][l]);                        \
            grad[3 * l] = nan ? NAN : g[0][l];                                                 \
            grad[3 * l + 1] = nan ? NAN : g[1][l];                                             \
            grad[3 * l + 2] = nan ? NAN : g[2][l];                                             \
        }                                                                                      \
    }
GRAD_BLOCK(grad_block_f32, float)
GRAD_BLOCK(grad_block_f64, double)
#undef GRAD_BLOCK

GEOM_SIMD_CLONES
static void grad_blocks(const geom_implicit_grid *d, size_t nb, const double *p, double *grad)
{
    double s[3], um[3], inv[3];
    for (int a = 0; a < 3; a++) {
        s[a] = d->spacing[a] > 0 ? d->spacing[a] : 1.0; /* trilinear.c's spacing_of */
        um[a] = (double)(d->dims[a] - 1);
        /* 1 / s when s and 2 s are powers of two with exact reciprocals
         * (dividing by them is multiplying by those), else 0 (divide) */
        int e;
        inv[a] = frexp(s[a], &e) == 0.5 && isfinite(2.0 * s[a]) && isfinite(1.0 / s[a]) &&
                         1.0 / s[a] * s[a] == 1.0
                     ? 1.0 / s[a]
                     : 0.0;
    }
    int64_t stride[3] = {1, (int64_t)d->dims[0], (int64_t)(d->dims[0] * d->dims[1])};
    for (size_t i = 0; i < nb; i++, p += 3 * GB, grad += 3 * GB) {
        if (d->type == GEOM_IMPLICIT_SCALAR_F32)
            grad_block_f32(d->origin, s, inv, um, stride, (const float *)d->data, p, grad);
        else
            grad_block_f64(d->origin, s, inv, um, stride, (const double *)d->data, p, grad);
    }
}

/* geom_implicit_samples_gradient at n points p of d (its own samples) into
 * grad, bitwise: blocks of GB points, then point by point. */
static void samples_gradients(const geom_implicit_grid *d, size_t n, const double *p,
                              double *grad)
{
    size_t done = 0;
    int fast = d->type == GEOM_IMPLICIT_SCALAR_F32 || d->type == GEOM_IMPLICIT_SCALAR_F64;
    for (int a = 0; a < 3; a++)
        fast &= d->dims[a] >= 2 && d->dims[a] <= INT32_MAX;
    if (fast && d->data) {
        done = n / GB * GB;
        grad_blocks(d, n / GB, p, grad);
    }
    for (size_t i = done; i < n; i++)
        geom_implicit_samples_gradient(d, NULL, p + 3 * i, grad + 3 * i);
}

void geom_implicit_volume_eval_many(const geom_implicit_volume *v, size_t n, const double *p,
                                    double *out, double *grad)
{
    if (!out)
        return;
    if (v && p) { /* the block interpolators: values (trilinear.c), gradients */
        geom_implicit_grid g;
        geom_implicit_volume_get_desc(v, &g);
        geom__implicit_samples_values(&g, n, p, out);
        if (grad)
            samples_gradients(&g, n, p, grad);
        return;
    }
    for (size_t i = 0; i < n; i++)
        out[i] = NAN;
}
