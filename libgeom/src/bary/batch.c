/*
 * Batch entry points of the barycentric functions: one call over n rows,
 * each argument either one row per query (stride = its size) or the same
 * for every row (stride 0), so bindings (numpy) pay the call overhead once.
 *
 * The common case of one simplex shared by every row gets its own loop: the
 * vertex differences, minors and permanents that do not depend on p are
 * computed once, and each row evaluates only its p-dependent terms with the
 * same certified filter as the single-point functions (relative error at
 * most 2^-42 per determinant). A row the filter cannot certify (a point on
 * or very near a face, a vertex, non-finite input) goes through the
 * single-point function, which evaluates it exactly.
 */
#include "bary/bary_internal.h"

#include <math.h>
#include <string.h>

static void finish_row(geom_status st, double *out, size_t k, int32_t *status, size_t i,
                       size_t *failed)
{
    if (st != GEOM_OK) {
        for (size_t j = 0; j < k; j++)
            out[j] = NAN;
        (*failed)++;
    }
    if (status)
        status[i] = (int32_t)st;
}

/* The filter of geom__bary_det2 without branches: 1 when x1*y2 - y1*x2 is
 * certified (an exact zero is left to the single-point function). */
static inline int64_t det2_ok(double x1, double y2, double y1, double x2, double *out)
{
    double t1 = x1 * y2, t2 = y1 * x2;
    double det = t1 - t2, sum = fabs(t1) + fabs(t2);
    *out = det;
    return (fabs(det) >= (GEOM_BARY_CCW_A * GEOM_BARY_REL) * sum + GEOM_BARY_TINY) &
           (sum < GEOM_BARY_BIG);
}

/* Rows per block of the shared-simplex loops: each block is computed without
 * branches, then its rows are checked only when one was not certified. */
#define BLOCK 64

/* Rows i0 .. i0+m-1 (m <= BLOCK) of 3 doubles at stride sp into lanes x, y,
 * z (the lanes past m repeat row i0); packed rows (sp 3) of a full block
 * de-interleave with a constant stride, which vectorises. */
GEOM__CLONE_INLINE void gather3(const double *p, size_t sp, size_t i0, size_t m,
                                double *restrict x, double *restrict y, double *restrict z)
{
    if (sp == 3 && m == BLOCK) {
        const double *q = p + 3 * i0;
        for (size_t j = 0; j < BLOCK; j++) {
            x[j] = q[3 * j];
            y[j] = q[3 * j + 1];
            z[j] = q[3 * j + 2];
        }
    } else {
        for (size_t j = 0; j < BLOCK; j++) {
            const double *q = p + (i0 + (j < m ? j : 0)) * sp;
            x[j] = q[0];
            y[j] = q[1];
            z[j] = q[2];
        }
    }
}

/* Lanes l[0..2] of m rows into o (3 doubles a row); a full block with a
 * constant count vectorises (interleaving stores). */
GEOM__CLONE_INLINE void store3(double *restrict o, size_t m, double (*l)[BLOCK])
{
    if (m == BLOCK) {
        for (size_t j = 0; j < BLOCK; j++) {
            o[3 * j] = l[0][j];
            o[3 * j + 1] = l[1][j];
            o[3 * j + 2] = l[2][j];
        }
    } else {
        for (size_t j = 0; j < m; j++) {
            o[3 * j] = l[0][j];
            o[3 * j + 1] = l[1][j];
            o[3 * j + 2] = l[2][j];
        }
    }
}

/* A certified N is never 0: a zero quotient underflowed; keep its sign
 * (IEEE gives the zero the quotient's sign). */
static inline double keep_tiny(double q)
{
    return q == 0.0 ? copysign(DBL_TRUE_MIN, q) : q;
}

/* The end of a block of m rows from row i0 of a shared-simplex kernel
 * (vertices v, k weights a row): every row OK when the block was certified
 * (all), else each uncertified row (!fast or !ok[j]) through the
 * single-point function, which evaluates it exactly. */
static void finish_block(geom_bary_simplex kind, const double *const v[4], const double *p,
                         size_t sp, size_t i0, size_t m, int fast, int all, const int64_t *ok,
                         double *out, int32_t *status, size_t *failed)
{
    size_t k = kind == GEOM_BARY_TET ? 4 : 3;
    if (all && !status)
        return;
    for (size_t j = 0; j < m; j++) {
        size_t i = i0 + j;
        if (all || (fast && ok[j])) {
            if (status)
                status[i] = GEOM_OK;
            continue;
        }
        double *o = out + k * i;
        geom_status st = kind == GEOM_BARY_TET    ? geom_bary_tet(v[0], v[1], v[2], v[3], p + i * sp, o)
                         : kind == GEOM_BARY_TRI3 ? geom_bary_tri3(v[0], v[1], v[2], p + i * sp, o)
                                                  : geom_bary_tri2(v[0], v[1], v[2], p + i * sp, o);
        finish_row(st, o, k, status, i, failed);
    }
}

/* tri2 over n points p (stride sp) in the one triangle (a, b, c): the very
 * expressions of geom_bary_tri2 (bitwise the same results), with the
 * triangle's differences and D computed once. Each block is gathered into
 * lanes (px, py), computed lane by lane without branches (the loops the
 * compiler vectorises; AVX2/AVX-512 clones), then stored; a block with an
 * uncertified row sends that row through geom_bary_tri2. */
GEOM_SIMD_CLONES
static void tri2_shared(const double a[2], const double b[2], const double c[2], size_t n,
                        const double *p, size_t sp, double *out, int32_t *status, size_t *failed)
{
    double acx = a[0] - c[0], acy = a[1] - c[1];
    double bcx = b[0] - c[0], bcy = b[1] - c[1];
    double d;
    int fast = geom__bary_finite(a, 2) && geom__bary_finite(b, 2) && geom__bary_finite(c, 2) &&
               geom__bary_det2(acx, bcy, acy, bcx, GEOM_BARY_REL, &d) && d != 0.0;
    const double ax = a[0], ay = a[1], bx = b[0], by = b[1], cx = c[0], cy = c[1];
    const double *const v[4] = {a, b, c, NULL};
    for (size_t i0 = 0; i0 < n; i0 += BLOCK) {
        size_t m = n - i0 < BLOCK ? n - i0 : BLOCK;
        int64_t ok[BLOCK];
        int all = fast;
        if (fast) {
            double px[BLOCK], py[BLOCK], l[3][BLOCK];
            if (sp == 2 && m == BLOCK) { /* packed points: a constant stride vectorises */
                const double *q = p + 2 * i0;
                for (size_t j = 0; j < BLOCK; j++) {
                    px[j] = q[2 * j];
                    py[j] = q[2 * j + 1];
                }
            } else {
                for (size_t j = 0; j < BLOCK; j++) {
                    const double *q = p + (i0 + (j < m ? j : 0)) * sp;
                    px[j] = q[0];
                    py[j] = q[1];
                }
            }
            int64_t acc = 1;
            for (size_t j = 0; j < BLOCK; j++) {
                double pcx = px[j] - cx, pcy = py[j] - cy;
                double apx = ax - px[j], apy = ay - py[j];
                double bpx = bx - px[j], bpy = by - py[j];
                double n0, n1, n2;
                ok[j] = det2_ok(pcx, bcy, pcy, bcx, &n0) & det2_ok(acx, pcy, acy, pcx, &n1) &
                        det2_ok(apx, bpy, apy, bpx, &n2);
                l[0][j] = keep_tiny(n0 / d);
                l[1][j] = keep_tiny(n1 / d);
                l[2][j] = keep_tiny(n2 / d);
                acc &= ok[j];
            }
            all = (int)acc;
            store3(out + 3 * i0, m, l);
        }
        finish_block(GEOM_BARY_TRI2, v, p, sp, i0, m, fast, all, ok, out, status, failed);
    }
}

/* tri3 over n points p (stride sp) projected onto the plane of the one
 * triangle (a, b, c): geom_bary_tri3's expressions (its cross products and
 * certified dot products, bitwise the same results) with the triangle's
 * edges, normal n and denominator n . n computed once; the p-dependent
 * terms lane by lane without branches. Blocks as tri2_shared; a row the
 * filter cannot certify goes through geom_bary_tri3. */
GEOM_SIMD_CLONES
static void tri3_shared(const double a[3], const double b[3], const double c[3], size_t n,
                        const double *p, size_t sp, double *out, int32_t *status, size_t *failed)
{
    double u[3], v[3], e0[3], e1[3], nn[3], na[3], d = 0.0;
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        e0[k] = c[k] - b[k];
        e1[k] = a[k] - c[k];
    }
    geom__bary_cross_abs(u, v, nn, na);
    int fast = geom__isfinite3(a) && geom__isfinite3(b) && geom__isfinite3(c) &&
               geom__bary_dot3_ok(nn, na, nn, na, &d);
    const double *const vv[4] = {a, b, c, NULL};
    const double A[3] = {a[0], a[1], a[2]}, B[3] = {b[0], b[1], b[2]}, C[3] = {c[0], c[1], c[2]};
    for (size_t i0 = 0; i0 < n; i0 += BLOCK) {
        size_t m = n - i0 < BLOCK ? n - i0 : BLOCK;
        int64_t ok[BLOCK];
        int all = fast;
        if (fast) {
            double px[BLOCK], py[BLOCK], pz[BLOCK], l[3][BLOCK];
            gather3(p, sp, i0, m, px, py, pz);
            int64_t acc = 1;
            for (size_t j = 0; j < BLOCK; j++) {
                const double f0[3] = {px[j] - B[0], py[j] - B[1], pz[j] - B[2]};
                const double f1[3] = {px[j] - C[0], py[j] - C[1], pz[j] - C[2]};
                const double f2[3] = {px[j] - A[0], py[j] - A[1], pz[j] - A[2]};
                double mm[3], ma[3], n0, n1, n2;
                geom__bary_cross_abs(e0, f0, mm, ma);
                int64_t k0 = geom__bary_dot3_ok(nn, na, mm, ma, &n0);
                geom__bary_cross_abs(e1, f1, mm, ma);
                int64_t k1 = geom__bary_dot3_ok(nn, na, mm, ma, &n1);
                geom__bary_cross_abs(u, f2, mm, ma);
                int64_t k2 = geom__bary_dot3_ok(nn, na, mm, ma, &n2);
                ok[j] = k0 & k1 & k2;
                l[0][j] = keep_tiny(n0 / d);
                l[1][j] = keep_tiny(n1 / d);
                l[2][j] = keep_tiny(n2 / d);
                acc &= ok[j];
            }
            all = (int)acc;
            store3(out + 3 * i0, m, l);
        }
        finish_block(GEOM_BARY_TRI3, vv, p, sp, i0, m, fast, all, ok, out, status, failed);
    }
}

/* tet over n points in the one tetrahedron (a, b, c, d): geom_bary_tet's
 * own determinants (geom__bary_det3 with p in place of each vertex, and D)
 * and quotients, lane by lane without branches (the terms that do not
 * depend on p are hoisted by the compiler: the same operations, the same
 * bits), so the weights are bitwise geom_bary_tet's; every row the filter
 * cannot certify goes through geom_bary_tet. Blocks as tri2_shared. */
GEOM_SIMD_CLONES
static void tet_shared(const double a[3], const double b[3], const double c[3],
                       const double d[3], size_t n, const double *p, size_t sp, double *out,
                       int32_t *status, size_t *failed)
{
    double vol;
    int fast = geom__isfinite3(a) && geom__isfinite3(b) && geom__isfinite3(c) && geom__isfinite3(d) &&
               geom__bary_det3(a, b, c, d, &vol) && vol != 0.0;
    const double *const v[4] = {a, b, c, d};
    for (size_t i0 = 0; i0 < n; i0 += BLOCK) {
        size_t mm = n - i0 < BLOCK ? n - i0 : BLOCK;
        int64_t ok[BLOCK];
        int all = fast;
        if (fast) {
            double px[BLOCK], py[BLOCK], pz[BLOCK], l[4][BLOCK];
            gather3(p, sp, i0, mm, px, py, pz);
            int64_t acc = 1;
            for (size_t j = 0; j < BLOCK; j++) {
                const double q[3] = {px[j], py[j], pz[j]};
                double n0, n1, n2, n3;
                ok[j] = geom__bary_det3(q, b, c, d, &n0) & geom__bary_det3(a, q, c, d, &n1) &
                        geom__bary_det3(a, b, q, d, &n2) & geom__bary_det3(a, b, c, q, &n3);
                l[0][j] = keep_tiny(n0 / vol);
                l[1][j] = keep_tiny(n1 / vol);
                l[2][j] = keep_tiny(n2 / vol);
                l[3][j] = keep_tiny(n3 / vol);
                acc &= ok[j];
            }
            all = (int)acc;
            double *o = out + 4 * i0;
            if (mm == BLOCK) /* a constant count vectorises (interleaving stores) */
                for (size_t j = 0; j < BLOCK; j++) {
                    o[4 * j] = l[0][j];
                    o[4 * j + 1] = l[1][j];
                    o[4 * j + 2] = l[2][j];
                    o[4 * j + 3] = l[3][j];
                }
            else
                for (size_t j = 0; j < mm; j++)
                    for (size_t k = 0; k < 4; k++)
                        o[4 * j + k] = l[k][j];
        }
        finish_block(GEOM_BARY_TET, v, p, sp, i0, mm, fast, all, ok, out, status, failed);
    }
}

geom_status geom_bary_simplex_many(geom_bary_simplex kind, size_t n, const double *const pts[5],
                                   const size_t strides[5], double *out, int32_t *status,
                                   size_t *n_failed)
{
    size_t failed = 0;
    if (n_failed)
        *n_failed = 0;
    if (n == 0)
        return GEOM_OK;
    int np = kind == GEOM_BARY_TET ? 5 : 4;
    size_t k = kind == GEOM_BARY_TET ? 4 : 3;
    if (!pts || !strides || !out || (kind != GEOM_BARY_TRI2 && kind != GEOM_BARY_TRI3 &&
                                      kind != GEOM_BARY_TET))
        return GEOM_ERR_INVALID_ARG;
    for (int a = 0; a < np; a++)
        if (!pts[a])
            return GEOM_ERR_INVALID_ARG;
    const double *a = pts[0], *b = pts[1], *c = pts[2], *d = pts[3], *p = pts[np - 1];
    size_t sa = strides[0], sb = strides[1], sc = strides[2], sd = strides[3],
           sp = strides[np - 1];
    if (kind == GEOM_BARY_TRI2 && sa == 0 && sb == 0 && sc == 0) {
        tri2_shared(a, b, c, n, p, sp, out, status, &failed);
        n = 0;
    } else if (kind == GEOM_BARY_TRI3 && sa == 0 && sb == 0 && sc == 0) {
        tri3_shared(a, b, c, n, p, sp, out, status, &failed);
        n = 0;
    } else if (kind == GEOM_BARY_TET && sa == 0 && sb == 0 && sc == 0 && sd == 0) {
        tet_shared(a, b, c, d, n, p, sp, out, status, &failed);
        n = 0;
    }
    for (size_t i = 0; i < n; i++) {
        double *o = out + k * i;
        geom_status st;
        if (kind == GEOM_BARY_TRI2)
            st = geom_bary_tri2(a + i * sa, b + i * sb, c + i * sc, p + i * sp, o);
        else if (kind == GEOM_BARY_TRI3)
            st = geom_bary_tri3(a + i * sa, b + i * sb, c + i * sc, p + i * sp, o);
        else
            st = geom_bary_tet(a + i * sa, b + i * sb, c + i * sc, d + i * sd, p + i * sp, o);
        finish_row(st, o, k, status, i, &failed);
    }
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}

geom_status geom_bary_polygon_many(int wachspress, size_t nv, const double *poly, size_t n,
                                   const double *p, double *w, int32_t *status, size_t *n_failed)
{
    size_t failed = 0;
    if (n_failed)
        *n_failed = 0;
    if (n == 0)
        return GEOM_OK;
    if (!poly || !p || !w || nv < 3)
        return GEOM_ERR_INVALID_ARG;
    for (size_t i = 0; i < n; i++) {
        double *o = w + nv * i;
        geom_status st = wachspress ? geom_bary_wachspress(nv, poly, p + 2 * i, o)
                                    : geom_bary_mean_value(nv, poly, p + 2 * i, o);
        finish_row(st, o, nv, status, i, &failed);
    }
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}

/* geom_bary_perspective over n rows, lane by lane without branches: its
 * quotients q = l / w, sum s = q0 + q1 + q2 and q / s (divisions and a sum:
 * no contraction, the same bits), with its conditions as a mask (finite
 * input, w != 0, max |q| in the range that needs no rescaling, s nonzero
 * and finite). A row outside the mask (the rescaled and failing cases) goes
 * through geom_bary_perspective. Packed rows (strides 3) in full blocks
 * de-interleave with constant strides, which vectorises. */
GEOM_SIMD_CLONES
static void perspective_rows(size_t n, const double *l, size_t sl, const double *w, size_t sw,
                             double *lp, int32_t *status, size_t *failed)
{
    for (size_t i0 = 0; i0 < n; i0 += BLOCK) {
        size_t m = n - i0 < BLOCK ? n - i0 : BLOCK;
        double L[3][BLOCK], W[3][BLOCK], o[3][BLOCK];
        int64_t ok[BLOCK];
        gather3(l, sl, i0, m, L[0], L[1], L[2]);
        gather3(w, sw, i0, m, W[0], W[1], W[2]);
        int64_t acc = 1;
        for (size_t j = 0; j < BLOCK; j++) {
            double q0 = L[0][j] / W[0][j], q1 = L[1][j] / W[1][j], q2 = L[2][j] / W[2][j];
            double s = q0 + q1 + q2;
            double a0 = fabs(q0), a1 = fabs(q1), a2 = fabs(q2);
            double big = a0 > a1 ? a0 : a1;
            big = big > a2 ? big : a2;
            ok[j] = (fabs(L[0][j]) <= DBL_MAX) & (fabs(L[1][j]) <= DBL_MAX) &
                    (fabs(L[2][j]) <= DBL_MAX) & (fabs(W[0][j]) <= DBL_MAX) &
                    (fabs(W[1][j]) <= DBL_MAX) & (fabs(W[2][j]) <= DBL_MAX) &
                    (W[0][j] != 0.0) & (W[1][j] != 0.0) & (W[2][j] != 0.0) &
                    (big < 0x1p1000) & ((big > 0x1p-1000) | (big == 0.0)) & (s != 0.0) &
                    (fabs(s) <= DBL_MAX);
            o[0][j] = q0 / s;
            o[1][j] = q1 / s;
            o[2][j] = q2 / s;
            acc &= ok[j];
        }
        /* rows outside the mask first (before the block is stored: a row
         * written over its own input still reads it) */
        for (size_t j = 0; j < m && !(acc && !status); j++) {
            size_t i = i0 + j;
            if (ok[j]) {
                if (status)
                    status[i] = GEOM_OK;
                continue;
            }
            double r[3];
            finish_row(geom_bary_perspective(l + i * sl, w + i * sw, r), r, 3, status, i, failed);
            for (size_t k = 0; k < 3; k++)
                o[k][j] = r[k];
        }
        store3(lp + 3 * i0, m, o);
    }
}

geom_status geom_bary_perspective_many(size_t n, const double *l, size_t sl, const double *w,
                                       size_t sw, double *lp, int32_t *status, size_t *n_failed)
{
    size_t failed = 0;
    if (n_failed)
        *n_failed = 0;
    if (n == 0)
        return GEOM_OK;
    if (!l || !w || !lp)
        return GEOM_ERR_INVALID_ARG;
    perspective_rows(n, l, sl, w, sw, lp, status, &failed);
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}

/* n rows of k weights l into out (ncomp per row), each output the sum of
 * geom_bary_interpolate in its order; with k and ncomp constants (the
 * callers below) the row's sums become vector operations. */
GEOM__CLONE_INLINE void interp_rows(size_t n, size_t k, const double *restrict l, size_t ncomp,
                                    const double *restrict attr, double *restrict out)
{
    for (size_t r = 0; r < n; r++)
        for (size_t j = 0; j < ncomp; j++) {
            double s = 0.0;
            for (size_t i = 0; i < k; i++)
                s += l[k * r + i] * attr[i * ncomp + j];
            out[ncomp * r + j] = s;
        }
}
GEOM_SIMD_CLONES
static void interp_many(size_t n, size_t k, const double *l, size_t ncomp, const double *attr,
                        double *out)
{
#define INTERP_CASE(K, C)                                                                      \
    if (k == K && ncomp == C) {                                                                \
        interp_rows(n, K, l, C, attr, out);                                                    \
        return;                                                                                \
    }
    INTERP_CASE(3, 1) INTERP_CASE(3, 2) INTERP_CASE(3, 3) INTERP_CASE(3, 4)
    INTERP_CASE(4, 1) INTERP_CASE(4, 2) INTERP_CASE(4, 3) INTERP_CASE(4, 4)
#undef INTERP_CASE
    interp_rows(n, k, l, ncomp, attr, out);
}

geom_status geom_bary_interpolate_many(size_t n, size_t k, const double *l, size_t ncomp,
                                       const double *attr, double *out)
{
    if (n == 0)
        return GEOM_OK;
    if (!l || !attr || !out || k == 0)
        return GEOM_ERR_INVALID_ARG;
    /* out over l or attr: row by row, as the single function does it */
    uintptr_t o0 = (uintptr_t)out, o1 = (uintptr_t)(out + ncomp * n);
    uintptr_t l0 = (uintptr_t)l, l1 = (uintptr_t)(l + k * n);
    uintptr_t a0 = (uintptr_t)attr, a1 = (uintptr_t)(attr + k * ncomp);
    if ((o0 < l1 && l0 < o1) || (o0 < a1 && a0 < o1)) {
        for (size_t i = 0; i < n; i++)
            (void)geom_bary_interpolate(k, l + k * i, ncomp, attr, out + ncomp * i);
        return GEOM_OK;
    }
    interp_many(n, k, l, ncomp, attr, out);
    return GEOM_OK;
}
