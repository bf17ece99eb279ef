/* 3x3 and 4x4 matrices (column-major): products, transpose, determinant,
 * inverse by adjugate/cofactors with a scale-invariant singularity test. */
#include "core/internal.h"

#define M3(a, r, c) ((a).m[3 * (c) + (r)])
#define M4(a, r, c) ((a).m[4 * (c) + (r)])

/* |det| below this times the product of the column norms (Hadamard's bound,
 * which |det| never exceeds) counts as singular. */
#define GEOM_SINGULAR_RTOL 1e-14

geom_mat3 geom_mat3_identity(void)
{
    geom_mat3 r = {{1, 0, 0, 0, 1, 0, 0, 0, 1}};
    return r;
}

geom_mat3 geom_mat3_mul(geom_mat3 a, geom_mat3 b)
{
    geom_mat3 r;
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 3; ++i)
            M3(r, i, c) = M3(a, i, 0) * M3(b, 0, c) + M3(a, i, 1) * M3(b, 1, c) +
                          M3(a, i, 2) * M3(b, 2, c);
    return r;
}

geom_vec3 geom_mat3_mul_vec3(geom_mat3 a, geom_vec3 v)
{
    return geom_vec3_make(M3(a, 0, 0) * v.x + M3(a, 0, 1) * v.y + M3(a, 0, 2) * v.z,
                          M3(a, 1, 0) * v.x + M3(a, 1, 1) * v.y + M3(a, 1, 2) * v.z,
                          M3(a, 2, 0) * v.x + M3(a, 2, 1) * v.y + M3(a, 2, 2) * v.z);
}

geom_mat3 geom_mat3_transpose(geom_mat3 a)
{
    geom_mat3 r;
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 3; ++i)
            M3(r, i, c) = M3(a, c, i);
    return r;
}

double geom_mat3_determinant(geom_mat3 a)
{
    return M3(a, 0, 0) * (M3(a, 1, 1) * M3(a, 2, 2) - M3(a, 2, 1) * M3(a, 1, 2)) -
           M3(a, 0, 1) * (M3(a, 1, 0) * M3(a, 2, 2) - M3(a, 2, 0) * M3(a, 1, 2)) +
           M3(a, 0, 2) * (M3(a, 1, 0) * M3(a, 2, 1) - M3(a, 2, 0) * M3(a, 1, 1));
}

static int all_finite(const double *m, int n)
{
    for (int i = 0; i < n; ++i)
        if (!isfinite(m[i]))
            return 0;
    return 1;
}

/* Scale each column c of the n x n matrix m by 2^-e[c] (exact) so that its
 * largest entry lies in [0.5, 1), and return the product of the scaled
 * columns' Euclidean norms (Hadamard's bound on |det| of the scaled matrix).
 * Inverting the scaled matrix B = A D^-1 and scaling the rows of B^-1 back
 * by D^-1 gives A^-1 without overflow or underflow whatever A's magnitude.
 * Returns 0 for a zero column. */
static double scale_columns(double *m, int n, int *e)
{
    double p = 1.0;
    for (int c = 0; c < n; ++c) {
        double mx = 0.0, s = 0.0;
        for (int r = 0; r < n; ++r)
            mx = fmax(mx, fabs(m[n * c + r]));
        if (mx == 0.0)
            return 0.0;
        frexp(mx, &e[c]);
        for (int r = 0; r < n; ++r) {
            m[n * c + r] = ldexp(m[n * c + r], -e[c]);
            s += m[n * c + r] * m[n * c + r];
        }
        p *= sqrt(s);
    }
    return p;
}

/* (B^-1) with rows scaled by 2^-e[r]: the inverse of the unscaled matrix. */
static void unscale_rows(double *inv, int n, const int *e)
{
    for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r)
            inv[n * c + r] = ldexp(inv[n * c + r], -e[r]);
}

geom_status geom_mat3_inverse(geom_mat3 a, geom_mat3 *out)
{
    geom_mat3 id = geom_mat3_identity();
    if (!all_finite(a.m, 9)) {
        if (out)
            *out = id;
        return GEOM_ERR_INVALID_ARG;
    }
    int e[3];
    double bound = scale_columns(a.m, 3, e);
    geom_mat3 adj;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
            /* cofactor of (r, c), stored transposed: adj(c, r) */
            M3(adj, c, r) = M3(a, r1, c1) * M3(a, r2, c2) - M3(a, r1, c2) * M3(a, r2, c1);
        }
    double det = M3(a, 0, 0) * M3(adj, 0, 0) + M3(a, 0, 1) * M3(adj, 1, 0) +
                 M3(a, 0, 2) * M3(adj, 2, 0);
    if (!(fabs(det) > GEOM_SINGULAR_RTOL * bound)) {
        if (out)
            *out = id;
        return GEOM_ERR_DEGENERATE;
    }
    if (out) {
        for (int i = 0; i < 9; ++i)
            out->m[i] = adj.m[i] / det;
        unscale_rows(out->m, 3, e);
    }
    return GEOM_OK;
}

geom_mat4 geom_mat4_identity(void)
{
    geom_mat4 r = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
    return r;
}

geom_mat4 geom_mat4_mul(geom_mat4 a, geom_mat4 b)
{
    geom_mat4 r;
    for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 4; ++i)
            M4(r, i, c) = M4(a, i, 0) * M4(b, 0, c) + M4(a, i, 1) * M4(b, 1, c) +
                          M4(a, i, 2) * M4(b, 2, c) + M4(a, i, 3) * M4(b, 3, c);
    return r;
}

geom_vec4 geom_mat4_mul_vec4(geom_mat4 a, geom_vec4 v)
{
    double in[4] = {v.x, v.y, v.z, v.w}, o[4];
    for (int i = 0; i < 4; ++i)
        o[i] = M4(a, i, 0) * in[0] + M4(a, i, 1) * in[1] + M4(a, i, 2) * in[2] +
               M4(a, i, 3) * in[3];
    return geom_vec4_make(o[0], o[1], o[2], o[3]);
}

geom_mat4 geom_mat4_transpose(geom_mat4 a)
{
    geom_mat4 r;
    for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 4; ++i)
            M4(r, i, c) = M4(a, c, i);
    return r;
}

/* Cofactor expansion through the 2x2 minors of the first two and last two
 * rows (Laplace expansion); adj receives the adjugate. Returns det. */
static double mat4_adjugate(const geom_mat4 *a, geom_mat4 *adj)
{
    const double *m = a->m;
    /* element (r, c) = m[4c + r]; work on rows of the transpose for brevity */
#define E(r, c) m[4 * (c) + (r)]
    double s0 = E(0, 0) * E(1, 1) - E(1, 0) * E(0, 1);
    double s1 = E(0, 0) * E(1, 2) - E(1, 0) * E(0, 2);
    double s2 = E(0, 0) * E(1, 3) - E(1, 0) * E(0, 3);
    double s3 = E(0, 1) * E(1, 2) - E(1, 1) * E(0, 2);
    double s4 = E(0, 1) * E(1, 3) - E(1, 1) * E(0, 3);
    double s5 = E(0, 2) * E(1, 3) - E(1, 2) * E(0, 3);
    double c5 = E(2, 2) * E(3, 3) - E(3, 2) * E(2, 3);
    double c4 = E(2, 1) * E(3, 3) - E(3, 1) * E(2, 3);
    double c3 = E(2, 1) * E(3, 2) - E(3, 1) * E(2, 2);
    double c2 = E(2, 0) * E(3, 3) - E(3, 0) * E(2, 3);
    double c1 = E(2, 0) * E(3, 2) - E(3, 0) * E(2, 2);
    double c0 = E(2, 0) * E(3, 1) - E(3, 0) * E(2, 1);
    double det = s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
    double *o = adj->m;
#define O(r, c) o[4 * (c) + (r)]
    O(0, 0) = E(1, 1) * c5 - E(1, 2) * c4 + E(1, 3) * c3;
    O(0, 1) = -E(0, 1) * c5 + E(0, 2) * c4 - E(0, 3) * c3;
    O(0, 2) = E(3, 1) * s5 - E(3, 2) * s4 + E(3, 3) * s3;
    O(0, 3) = -E(2, 1) * s5 + E(2, 2) * s4 - E(2, 3) * s3;
    O(1, 0) = -E(1, 0) * c5 + E(1, 2) * c2 - E(1, 3) * c1;
    O(1, 1) = E(0, 0) * c5 - E(0, 2) * c2 + E(0, 3) * c1;
    O(1, 2) = -E(3, 0) * s5 + E(3, 2) * s2 - E(3, 3) * s1;
    O(1, 3) = E(2, 0) * s5 - E(2, 2) * s2 + E(2, 3) * s1;
    O(2, 0) = E(1, 0) * c4 - E(1, 1) * c2 + E(1, 3) * c0;
    O(2, 1) = -E(0, 0) * c4 + E(0, 1) * c2 - E(0, 3) * c0;
    O(2, 2) = E(3, 0) * s4 - E(3, 1) * s2 + E(3, 3) * s0;
    O(2, 3) = -E(2, 0) * s4 + E(2, 1) * s2 - E(2, 3) * s0;
    O(3, 0) = -E(1, 0) * c3 + E(1, 1) * c1 - E(1, 2) * c0;
    O(3, 1) = E(0, 0) * c3 - E(0, 1) * c1 + E(0, 2) * c0;
    O(3, 2) = -E(3, 0) * s3 + E(3, 1) * s1 - E(3, 2) * s0;
    O(3, 3) = E(2, 0) * s3 - E(2, 1) * s1 + E(2, 2) * s0;
#undef O
#undef E
    return det;
}

double geom_mat4_determinant(geom_mat4 a)
{
    geom_mat4 adj;
    return mat4_adjugate(&a, &adj);
}

geom_status geom_mat4_inverse(geom_mat4 a, geom_mat4 *out)
{
    geom_mat4 id = geom_mat4_identity();
    if (!all_finite(a.m, 16)) {
        if (out)
            *out = id;
        return GEOM_ERR_INVALID_ARG;
    }
    int e[4];
    double bound = scale_columns(a.m, 4, e);
    geom_mat4 adj;
    double det = mat4_adjugate(&a, &adj);
    if (!(fabs(det) > GEOM_SINGULAR_RTOL * bound)) {
        if (out)
            *out = id;
        return GEOM_ERR_DEGENERATE;
    }
    if (out) {
        for (int i = 0; i < 16; ++i)
            out->m[i] = adj.m[i] / det;
        unscale_rows(out->m, 4, e);
    }
    return GEOM_OK;
}

geom_mat3 geom_mat4_upper3(geom_mat4 a)
{
    geom_mat3 r;
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 3; ++i)
            M3(r, i, c) = M4(a, i, c);
    return r;
}

geom_status geom_mat4_normal_matrix(geom_mat4 a, geom_mat3 *out)
{
    geom_mat3 inv;
    geom_status s = geom_mat3_inverse(geom_mat4_upper3(a), &inv);
    if (out)
        *out = s == GEOM_OK ? geom_mat3_transpose(inv) : geom_mat3_identity();
    return s;
}
