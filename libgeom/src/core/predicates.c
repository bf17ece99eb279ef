/*
 * Exact geometric predicates: orient2d, orient3d, incircle (Shewchuk 1997).
 *
 * Each predicate first evaluates the determinant in floating point together
 * with a bound on its rounding error (Shewchuk's "stage A" bounds, plus an
 * absolute term that covers gradual underflow of the products); when the
 * value exceeds the bound its sign is certain and it is returned as is.
 * Otherwise the determinant is evaluated exactly (expansion arithmetic on
 * power-of-two scaled input, or a big-float fallback for extreme dynamic
 * range; see expansion.c) and rounded.
 */
#include "core/expansion.h"
#include "core/internal.h"

/* Shewchuk's machine epsilon: half an ulp of 1. */
#define GEOM_EPS 0x1p-53
static const double ccw_errbound_a = (3.0 + 16.0 * GEOM_EPS) * GEOM_EPS;
static const double o3d_errbound_a = (7.0 + 56.0 * GEOM_EPS) * GEOM_EPS;
static const double icc_errbound_a = (10.0 + 96.0 * GEOM_EPS) * GEOM_EPS;
/* Absolute error allowance for products that underflow: each such product
 * is off by at most 2^-1075, far below this. It is a normal number on
 * purpose: arithmetic on subnormal operands is very slow on common CPUs.
 * (Determinants below about 2^-960 simply take the exact path.) */
#define GEOM_UNDERFLOW_TINY 0x1p-960

static int finite2(const double p[2])
{
    return isfinite(p[0]) && isfinite(p[1]);
}

/* Sign-preserving double of an exact value. */
static double xval_result(geom__xval v)
{
    return geom__xval_to_double(v);
}

static double orient2d_slow(const double a[2], const double b[2], const double c[2], double acx,
                            double bcy, double acy, double bcx)
{
    if (!finite2(a) || !finite2(b) || !finite2(c))
        return NAN;
    /* Both products have an exactly zero factor: the determinant is 0. */
    if ((acx == 0.0 || bcy == 0.0) && (acy == 0.0 || bcx == 0.0))
        return 0.0;
    return xval_result(geom__xeval_orient2d(a, b, c));
}

/* Shewchuk's first orient2d stage: *det, and whether its sign is certain
 * (Inf/NaN anywhere makes errbound Inf or NaN and the test fails). Branch
 * free, so the batch below vectorises it. */
static inline int orient2d_filter(double acx, double bcx, double acy, double bcy, double *det)
{
    double detleft = acx * bcy;
    double detright = acy * bcx;
    double errbound = ccw_errbound_a * (fabs(detleft) + fabs(detright)) + GEOM_UNDERFLOW_TINY;
    *det = detleft - detright;
    return (*det > errbound) | (-*det > errbound);
}

double geom_orient2d(const double a[2], const double b[2], const double c[2])
{
    double acx = a[0] - c[0], bcx = b[0] - c[0];
    double acy = a[1] - c[1], bcy = b[1] - c[1];
    double det;
    if (orient2d_filter(acx, bcx, acy, bcy, &det))
        return det;
    return orient2d_slow(a, b, c, acx, bcy, acy, bcx);
}

double geom_orient2d_exact(const double a[2], const double b[2], const double c[2])
{
    if (!finite2(a) || !finite2(b) || !finite2(c))
        return NAN;
    return xval_result(geom__xeval_orient2d(a, b, c));
}

double geom_orient3d(const double a[3], const double b[3], const double c[3], const double d[3])
{
    double permanent, zterm;
    double det = geom__orient3d_fast(a, b, c, d, &permanent, &zterm);
    /* An underflowed inner product is off by 2^-1075 and then multiplied by
     * a z difference. */
    double errbound = o3d_errbound_a * permanent + GEOM_UNDERFLOW_TINY * zterm;
    if (det > errbound || -det > errbound)
        return det;
    if (!geom__isfinite3(a) || !geom__isfinite3(b) || !geom__isfinite3(c) || !geom__isfinite3(d))
        return NAN;
    return xval_result(geom__xeval_orient3d(a, b, c, d));
}

double geom_orient3d_exact(const double a[3], const double b[3], const double c[3],
                           const double d[3])
{
    if (!geom__isfinite3(a) || !geom__isfinite3(b) || !geom__isfinite3(c) || !geom__isfinite3(d))
        return NAN;
    return xval_result(geom__xeval_orient3d(a, b, c, d));
}

double geom_incircle(const double a[2], const double b[2], const double c[2], const double d[2])
{
    double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
    double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];

    double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    double alift = adx * adx + ady * ady;
    double cdxady = cdx * ady, adxcdy = adx * cdy;
    double blift = bdx * bdx + bdy * bdy;
    double adxbdy = adx * bdy, bdxady = bdx * ady;
    double clift = cdx * cdx + cdy * cdy;

    double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
    double pa = fabs(bdxcdy) + fabs(cdxbdy);
    double pb = fabs(cdxady) + fabs(adxcdy);
    double pc = fabs(adxbdy) + fabs(bdxady);
    double permanent = pa * alift + pb * blift + pc * clift;
    /* Underflowed products (inner ones, squares) are off by 2^-1075 each and
     * are multiplied by a lift or by a cofactor. */
    double errbound = icc_errbound_a * permanent +
                      GEOM_UNDERFLOW_TINY * (1.0 + alift + blift + clift + pa + pb + pc);
    if (det > errbound || -det > errbound)
        return det;
    if (!finite2(a) || !finite2(b) || !finite2(c) || !finite2(d))
        return NAN;
    return xval_result(geom__xeval_incircle(a, b, c, d));
}

/* orient2d (three 2D points a, b, c) or orient3d (three = 1: four 3D points
 * a, b, c, d) over n rows (row i of a at a + i*sa, ...): the single-point
 * predicate's own filter (orient2d_filter; geom__orient3d_fast and its
 * errbound), lane by lane in blocks without branches (the loops the
 * compiler vectorises), so every certified row gets its very value; each row
 * the filter cannot certify goes through geom_orient2d / geom_orient3d (the
 * same bits). `three` is a constant at both call sites, so each clone keeps
 * one branch-free body. */
#define PREDICATE_BLOCK 64
GEOM__CLONE_INLINE void predicate_blocks(int three, size_t n, const double *a, size_t sa,
                                         const double *b, size_t sb, const double *c, size_t sc,
                                         const double *d, size_t sd, double *out)
{
    const int dim = three ? 3 : 2;
    for (size_t i0 = 0; i0 < n; i0 += PREDICATE_BLOCK) {
        size_t m = n - i0 < PREDICATE_BLOCK ? n - i0 : PREDICATE_BLOCK;
        double v[12][PREDICATE_BLOCK], det[PREDICATE_BLOCK];
        int64_t ok[PREDICATE_BLOCK], all = 1;
        for (size_t j = 0; j < PREDICATE_BLOCK; j++) {
            size_t i = i0 + (j < m ? j : 0);
            for (int k = 0; k < dim; k++) {
                v[k][j] = a[i * sa + k];
                v[3 + k][j] = b[i * sb + k];
                v[6 + k][j] = c[i * sc + k];
                if (three)
                    v[9 + k][j] = d[i * sd + k];
            }
        }
        for (size_t j = 0; j < PREDICATE_BLOCK; j++) {
            if (three) {
                const double pa[3] = {v[0][j], v[1][j], v[2][j]}, pb[3] = {v[3][j], v[4][j], v[5][j]};
                const double pc[3] = {v[6][j], v[7][j], v[8][j]}, pd[3] = {v[9][j], v[10][j], v[11][j]};
                double permanent, zterm;
                det[j] = geom__orient3d_fast(pa, pb, pc, pd, &permanent, &zterm);
                double errbound = o3d_errbound_a * permanent + GEOM_UNDERFLOW_TINY * zterm;
                ok[j] = (det[j] > errbound) | (-det[j] > errbound);
            } else {
                ok[j] = orient2d_filter(v[0][j] - v[6][j], v[3][j] - v[6][j], v[1][j] - v[7][j],
                                        v[4][j] - v[7][j], &det[j]);
            }
            all &= ok[j];
        }
        for (size_t j = 0; j < m; j++) {
            size_t i = i0 + j;
            out[i] = all || ok[j] ? det[j]
                     : three      ? geom_orient3d(a + i * sa, b + i * sb, c + i * sc, d + i * sd)
                                  : geom_orient2d(a + i * sa, b + i * sb, c + i * sc);
        }
    }
}

GEOM_SIMD_CLONES
static void orient2d_blocks(size_t n, const double *a, size_t sa, const double *b, size_t sb,
                            const double *c, size_t sc, double *out)
{
    predicate_blocks(0, n, a, sa, b, sb, c, sc, NULL, 0, out);
}

GEOM_SIMD_CLONES
static void orient3d_blocks(size_t n, const double *a, size_t sa, const double *b, size_t sb,
                            const double *c, size_t sc, const double *d, size_t sd, double *out)
{
    predicate_blocks(1, n, a, sa, b, sb, c, sc, d, sd, out);
}

/* Not clones themselves: a target_clones function with external linkage gets
 * an exported resolver despite -fvisibility=hidden. */
void geom__orient2d_many(size_t n, const double *a, size_t sa, const double *b, size_t sb,
                         const double *c, size_t sc, double *out)
{
    orient2d_blocks(n, a, sa, b, sb, c, sc, out);
}

void geom__orient3d_many(size_t n, const double *a, size_t sa, const double *b, size_t sb,
                         const double *c, size_t sc, const double *d, size_t sd, double *out)
{
    orient3d_blocks(n, a, sa, b, sb, c, sc, d, sd, out);
}
