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

/* A certified N is never 0: a zero quotient underflowed; keep its sign
 * (IEEE gives the zero the quotient's sign). */
static inline double keep_tiny(double q)
{
    return q == 0.0 ? copysign(DBL_TRUE_MIN, q) : q;
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
    for (size_t i0 = 0; i0 < n; i0 += BLOCK) {
        size_t m = n - i0 < BLOCK ? n - i0 : BLOCK;
        int64_t ok[BLOCK];
        int all = fast;
        if (fast) {
            double px[BLOCK], py[BLOCK], l0[BLOCK], l1[BLOCK], l2[BLOCK];
            for (size_t j = 0; j < BLOCK; j++) {
                const double *q = p + (i0 + (j < m ? j : 0)) * sp;
                px[j] = q[0];
                py[j] = q[1];
            }
            int64_t acc = 1;
            for (size_t j = 0; j < BLOCK; j++) {
                double pcx = px[j] - cx, pcy = py[j] - cy;
                double apx = ax - px[j], apy = ay - py[j];
                double bpx = bx - px[j], bpy = by - py[j];
                double n0, n1, n2;
                ok[j] = det2_ok(pcx, bcy, pcy, bcx, &n0) & det2_ok(acx, pcy, acy, pcx, &n1) &
                        det2_ok(apx, bpy, apy, bpx, &n2);
                l0[j] = keep_tiny(n0 / d);
                l1[j] = keep_tiny(n1 / d);
                l2[j] = keep_tiny(n2 / d);
                acc &= ok[j];
            }
            all = (int)acc;
            double *o = out + 3 * i0;
            if (m == BLOCK) { /* a constant count vectorises (interleaving stores) */
                for (size_t j = 0; j < BLOCK; j++) {
                    o[3 * j] = l0[j];
                    o[3 * j + 1] = l1[j];
                    o[3 * j + 2] = l2[j];
                }
            } else {
                for (size_t j = 0; j < m; j++) {
                    o[3 * j] = l0[j];
                    o[3 * j + 1] = l1[j];
                    o[3 * j + 2] = l2[j];
                }
            }
        }
        if (all) {
            if (status)
                for (size_t j = 0; j < m; j++)
                    status[i0 + j] = GEOM_OK;
            continue;
        }
        for (size_t j = 0; j < m; j++) {
            size_t i = i0 + j;
            double *o = out + 3 * i;
            if (fast && ok[j]) {
                if (status)
                    status[i] = GEOM_OK;
                continue;
            }
            finish_row(geom_bary_tri2(a, b, c, p + i * sp, o), o, 3, status, i, failed);
        }
    }
}

/* One 3x3 determinant expanded along the row r = (x, y, z) with the other
 * two rows' minors m and permanents pm fixed: the evaluation Shewchuk's
 * orient3d bound covers (any row order), so the same filter certifies it. */
static inline int64_t det3_row(double x, double y, double z, const double m[3], const double pm[3],
                           double *out)
{
    double det = x * m[0] + y * m[1] + z * m[2];
    double ax = fabs(x), ay = fabs(y), az = fabs(z);
    double perm = ax * pm[0] + ay * pm[1] + az * pm[2];
    double tiny = GEOM_BARY_TINY * (1.0 + ax + ay + az);
    *out = det;
    return (fabs(det) >= (GEOM_BARY_O3D_A * GEOM_BARY_REL) * perm + tiny) &
           (perm < GEOM_BARY_BIG);
}

/* Minors and permanents of rows u, v for the expansion along the other row
 * (placed first): det[r; u; v] = r . (u x v). */
static void minors(const double u[3], const double v[3], double m[3], double pm[3])
{
    double t[6] = {u[1] * v[2], u[2] * v[1], u[2] * v[0], u[0] * v[2], u[0] * v[1], u[1] * v[0]};
    for (int k = 0; k < 3; k++) {
        m[k] = t[2 * k] - t[2 * k + 1];
        pm[k] = fabs(t[2 * k]) + fabs(t[2 * k + 1]);
    }
}

static void sub3(const double a[3], const double b[3], double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = a[k] - b[k];
}

/* tet over n points in the one tetrahedron (a, b, c, d). With p in place of
 * a vertex, the determinant is linear in p: N_a = (p-d).((b-d)x(c-d)),
 * N_b = (p-d).((c-d)x(a-d)), N_c = (p-d).((a-d)x(b-d)), and N_d, by
 * translation invariance, (p-c).((b-c)x(a-c)). Each is certified on its own;
 * the weights agree with geom_bary_tet's within its stated accuracy (the
 * rounding of a certified value may differ in the last bits), and every row
 * the filter cannot certify is geom_bary_tet's own result. */
GEOM_SIMD_CLONES
static void tet_shared(const double a[3], const double b[3], const double c[3],
                       const double d[3], size_t n, const double *p, size_t sp, double *out,
                       int32_t *status, size_t *failed)
{
    double ad[3], bd[3], cd[3], ac[3], bc[3];
    sub3(a, d, ad);
    sub3(b, d, bd);
    sub3(c, d, cd);
    sub3(a, c, ac);
    sub3(b, c, bc);
    double m[4][3], pm[4][3];
    minors(bd, cd, m[0], pm[0]);
    minors(cd, ad, m[1], pm[1]);
    minors(ad, bd, m[2], pm[2]);
    minors(bc, ac, m[3], pm[3]);
    double vol;
    int fast = geom__isfinite3(a) && geom__isfinite3(b) && geom__isfinite3(c) && geom__isfinite3(d) &&
               det3_row(ad[0], ad[1], ad[2], m[0], pm[0], &vol) && vol != 0.0;
    for (size_t i0 = 0; i0 < n; i0 += BLOCK) {
        size_t mm = n - i0 < BLOCK ? n - i0 : BLOCK;
        int64_t ok[BLOCK];
        int all = fast;
        if (fast) {
            double px[BLOCK], py[BLOCK], pz[BLOCK], l[4][BLOCK];
            for (size_t j = 0; j < BLOCK; j++) {
                const double *q = p + (i0 + (j < mm ? j : 0)) * sp;
                px[j] = q[0];
                py[j] = q[1];
                pz[j] = q[2];
            }
            int64_t acc = 1;
            for (size_t j = 0; j < BLOCK; j++) {
                double x = px[j] - d[0], y = py[j] - d[1], z = pz[j] - d[2];
                double xc = px[j] - c[0], yc = py[j] - c[1], zc = pz[j] - c[2];
                double n0, n1, n2, n3;
                ok[j] = det3_row(x, y, z, m[0], pm[0], &n0) & det3_row(x, y, z, m[1], pm[1], &n1) &
                        det3_row(x, y, z, m[2], pm[2], &n2) &
                        det3_row(xc, yc, zc, m[3], pm[3], &n3);
                l[0][j] = keep_tiny(n0 / vol);
                l[1][j] = keep_tiny(n1 / vol);
                l[2][j] = keep_tiny(n2 / vol);
                l[3][j] = keep_tiny(n3 / vol);
                acc &= ok[j];
            }
            all = (int)acc;
            double *o = out + 4 * i0;
            if (mm == BLOCK) /* a constant count vectorises (interleaving stores) */
                for (size_t j = 0; j < BLOCK; j++)
                    for (size_t k = 0; k < 4; k++)
                        o[4 * j + k] = l[k][j];
            else
                for (size_t j = 0; j < mm; j++)
                    for (size_t k = 0; k < 4; k++)
                        o[4 * j + k] = l[k][j];
        }
        if (all) {
            if (status)
                for (size_t j = 0; j < mm; j++)
                    status[i0 + j] = GEOM_OK;
            continue;
        }
        for (size_t j = 0; j < mm; j++) {
            size_t i = i0 + j;
            double *o = out + 4 * i;
            if (fast && ok[j]) {
                if (status)
                    status[i] = GEOM_OK;
                continue;
            }
            finish_row(geom_bary_tet(a, b, c, d, p + i * sp, o), o, 4, status, i, failed);
        }
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
