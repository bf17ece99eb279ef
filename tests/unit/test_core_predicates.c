/*
 * Exact predicates (orient2d, orient3d, incircle and the _exact values)
 * against an exact reference computed here, independently of the library:
 * the inputs are dyadic, so after multiplying by a power of two they are
 * integers, and the determinants are evaluated in 512-bit two's-complement
 * integer arithmetic written in this file.
 */
#include "unit/test_util.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "geom/core.h"

/* ------------------------------------------------ 512-bit reference ints */

#define BI_LIMBS 16
typedef struct bi {
    uint32_t w[BI_LIMBS]; /* two's complement, little-endian limbs */
} bi;

static bi bi_from_i64(int64_t v)
{
    bi r;
    uint64_t u = (uint64_t)v;
    uint32_t fill = v < 0 ? 0xffffffffu : 0u;
    for (int i = 0; i < BI_LIMBS; i++)
        r.w[i] = fill;
    r.w[0] = (uint32_t)u;
    r.w[1] = (uint32_t)(u >> 32);
    return r;
}

static bi bi_add(bi a, bi b)
{
    bi r;
    uint64_t c = 0;
    for (int i = 0; i < BI_LIMBS; i++) {
        uint64_t s = (uint64_t)a.w[i] + b.w[i] + c;
        r.w[i] = (uint32_t)s;
        c = s >> 32;
    }
    return r;
}

static bi bi_neg(bi a)
{
    for (int i = 0; i < BI_LIMBS; i++)
        a.w[i] = ~a.w[i];
    return bi_add(a, bi_from_i64(1));
}

static bi bi_sub(bi a, bi b)
{
    return bi_add(a, bi_neg(b));
}

static int bi_sign(bi a)
{
    if (a.w[BI_LIMBS - 1] & 0x80000000u)
        return -1;
    for (int i = 0; i < BI_LIMBS; i++)
        if (a.w[i])
            return 1;
    return 0;
}

static bi bi_mul(bi a, bi b)
{
    int neg = 0;
    if (bi_sign(a) < 0) {
        a = bi_neg(a);
        neg ^= 1;
    }
    if (bi_sign(b) < 0) {
        b = bi_neg(b);
        neg ^= 1;
    }
    uint32_t t[BI_LIMBS] = {0};
    for (int i = 0; i < BI_LIMBS; i++) {
        uint64_t c = 0;
        for (int j = 0; i + j < BI_LIMBS; j++) {
            uint64_t cur = (uint64_t)a.w[i] * b.w[j] + t[i + j] + c;
            t[i + j] = (uint32_t)cur;
            c = cur >> 32;
        }
    }
    bi r;
    memcpy(r.w, t, sizeof t);
    return neg ? bi_neg(r) : r;
}

/* The double nearest to a * 2^e (round to nearest even), by hand. */
static double bi_to_double(bi a, int e)
{
    int s = bi_sign(a);
    if (s == 0)
        return 0.0;
    if (s < 0)
        a = bi_neg(a);
    int top = BI_LIMBS - 1;
    while (a.w[top] == 0)
        top--;
    int len = 32 * top;
    for (uint32_t x = a.w[top]; x; x >>= 1)
        len++;
    /* The 54 leading bits (53 + a rounding bit) and a sticky flag. */
    uint64_t m = 0;
    int sticky = 0;
    for (int bit = len - 1; bit >= 0; bit--) {
        int v = (a.w[bit / 32] >> (bit % 32)) & 1u;
        if (len - 1 - bit < 54)
            m = (m << 1) | (uint64_t)v;
        else if (v)
            sticky = 1;
    }
    int got = len < 54 ? len : 54;
    int shift = len - got; /* value = m * 2^shift (+ sticky) */
    if (got == 54) {
        int round = (int)(m & 1u);
        m >>= 1;
        shift++;
        if (round && (sticky || (m & 1u)))
            m++;
    }
    double r = ldexp((double)m, shift + e);
    return s < 0 ? -r : r;
}

/* x * 2^e as an exact integer. */
static int64_t units(double x, int e)
{
    double y = ldexp(x, e);
    assert_true(fabs(y) < 0x1p62);
    assert_true(y == floor(y));
    return (int64_t)y;
}

static bi bd(double x, double y, int e)
{
    return bi_sub(bi_from_i64(units(x, e)), bi_from_i64(units(y, e)));
}

/* Exact determinants in units of 2^-e per coordinate. */
static bi ref_orient2d(const double a[2], const double b[2], const double c[2], int e)
{
    return bi_sub(bi_mul(bd(a[0], c[0], e), bd(b[1], c[1], e)),
                  bi_mul(bd(a[1], c[1], e), bd(b[0], c[0], e)));
}

static bi ref_orient3d(const double a[3], const double b[3], const double c[3], const double d[3],
                       int e)
{
    bi m[3][3];
    const double *r[3] = {a, b, c};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            m[i][j] = bd(r[i][j], d[j], e);
    /* cofactor expansion along the first row */
    bi t0 = bi_sub(bi_mul(m[1][1], m[2][2]), bi_mul(m[1][2], m[2][1]));
    bi t1 = bi_sub(bi_mul(m[1][0], m[2][2]), bi_mul(m[1][2], m[2][0]));
    bi t2 = bi_sub(bi_mul(m[1][0], m[2][1]), bi_mul(m[1][1], m[2][0]));
    return bi_add(bi_sub(bi_mul(m[0][0], t0), bi_mul(m[0][1], t1)), bi_mul(m[0][2], t2));
}

static bi ref_incircle(const double a[2], const double b[2], const double c[2], const double d[2],
                       int e)
{
    const double *r[3] = {a, b, c};
    bi x[3], y[3], lift[3];
    for (int i = 0; i < 3; i++) {
        x[i] = bd(r[i][0], d[0], e);
        y[i] = bd(r[i][1], d[1], e);
        lift[i] = bi_add(bi_mul(x[i], x[i]), bi_mul(y[i], y[i]));
    }
    /* det [x y lift] expanded along the lift column */
    bi m0 = bi_sub(bi_mul(x[1], y[2]), bi_mul(y[1], x[2]));
    bi m1 = bi_sub(bi_mul(x[0], y[2]), bi_mul(y[0], x[2]));
    bi m2 = bi_sub(bi_mul(x[0], y[1]), bi_mul(y[0], x[1]));
    return bi_add(bi_sub(bi_mul(lift[0], m0), bi_mul(lift[1], m1)), bi_mul(lift[2], m2));
}

static int sgn(double x)
{
    return (x > 0.0) - (x < 0.0);
}

/* The textbook formulas in plain floating point, to show they fail. */
static double naive_orient2d(const double a[2], const double b[2], const double c[2])
{
    return (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
}

static double naive_orient3d(const double a[3], const double b[3], const double c[3],
                             const double d[3])
{
    double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
    double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
    double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
    return adx * (bdy * cdz - bdz * cdy) - ady * (bdx * cdz - bdz * cdx) +
           adz * (bdx * cdy - bdy * cdx);
}

static double naive_incircle(const double a[2], const double b[2], const double c[2],
                             const double d[2])
{
    double adx = a[0] - d[0], ady = a[1] - d[1];
    double bdx = b[0] - d[0], bdy = b[1] - d[1];
    double cdx = c[0] - d[0], cdy = c[1] - d[1];
    return (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
           (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
           (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
}

/* ------------------------------------------------------------- tests */

static void test_closed_forms(void **state)
{
    (void)state;
    const double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1};
    assert_true(geom_orient2d(a, b, c) == 1.0);
    assert_true(geom_orient2d(a, c, b) == -1.0);
    assert_true(geom_orient2d_exact(a, b, c) == 1.0);
    const double m[2] = {0.5, 0};
    assert_true(geom_orient2d(a, b, m) == 0.0);
    assert_true(geom_orient2d_exact(a, b, m) == 0.0);

    const double p[3] = {0, 0, 0}, q[3] = {1, 0, 0}, r[3] = {0, 1, 0};
    const double below[3] = {0, 0, -1}, above[3] = {0, 0, 2}, on[3] = {3, -7, 0};
    assert_true(geom_orient3d(p, q, r, below) == 1.0);
    assert_true(geom_orient3d(p, q, r, above) == -2.0);
    assert_true(geom_orient3d(p, q, r, on) == 0.0);
    assert_true(geom_orient3d_exact(p, q, r, below) == 1.0);

    /* circle through (1,0), (0,1), (-1,0): center 0, radius 1 */
    const double u[2] = {1, 0}, v[2] = {0, 1}, w[2] = {-1, 0};
    const double in[2] = {0, 0}, out[2] = {2, 0}, onc[2] = {0, -1};
    assert_true(geom_incircle(u, v, w, in) > 0.0);
    assert_true(geom_incircle(u, v, w, out) < 0.0);
    assert_true(geom_incircle(u, v, w, onc) == 0.0);
    assert_true(geom_incircle(w, v, u, in) < 0.0); /* clockwise flips */
}

/* Every triple (quadruple) of points of a small integer grid: signs equal the
 * exact integer determinants, and the _exact values equal them exactly. */
static void test_integer_grid(void **state)
{
    (void)state;
    double g[25][2];
    for (int i = 0; i < 25; i++) {
        g[i][0] = (double)(i % 5) - 2.0;
        g[i][1] = (double)(i / 5) - 2.0;
    }
    for (int i = 0; i < 25; i++)
        for (int j = 0; j < 25; j++)
            for (int k = 0; k < 25; k++) {
                bi r = ref_orient2d(g[i], g[j], g[k], 0);
                assert_int_equal(sgn(geom_orient2d(g[i], g[j], g[k])), bi_sign(r));
                assert_true(geom_orient2d_exact(g[i], g[j], g[k]) == bi_to_double(r, 0));
            }
    for (int i = 0; i < 25; i += 2)
        for (int j = 1; j < 25; j += 3)
            for (int k = 0; k < 25; k++)
                for (int l = 0; l < 25; l += 4) {
                    bi r = ref_incircle(g[i], g[j], g[k], g[l], 0);
                    assert_int_equal(sgn(geom_incircle(g[i], g[j], g[k], g[l])), bi_sign(r));
                }
    double h[27][3];
    for (int i = 0; i < 27; i++) {
        h[i][0] = (double)(i % 3) - 1.0;
        h[i][1] = (double)((i / 3) % 3) - 1.0;
        h[i][2] = (double)(i / 9) - 1.0;
    }
    for (int i = 0; i < 27; i++)
        for (int j = 0; j < 27; j += 2)
            for (int k = 0; k < 27; k++)
                for (int l = 0; l < 27; l += 3) {
                    bi r = ref_orient3d(h[i], h[j], h[k], h[l], 0);
                    assert_int_equal(sgn(geom_orient3d(h[i], h[j], h[k], h[l])), bi_sign(r));
                    assert_true(geom_orient3d_exact(h[i], h[j], h[k], h[l]) ==
                                bi_to_double(r, 0));
                }
}

/* Kettner et al.'s classroom example: p = (0.5 + i u, 0.5 + j u) with
 * u = 2^-53, q = (12, 12), r = (24, 24). The naive formula gets many signs
 * wrong; ours matches the exact sign everywhere. Also under exact
 * power-of-two scalings to the ends of the exponent range. */
static void test_orient2d_near_degenerate(void **state)
{
    (void)state;
    const double u = 0x1p-53;
    const double q[2] = {12, 12}, r[2] = {24, 24};
    int naive_wrong = 0, n = 0;
    for (int i = 0; i < 256; i++) {
        for (int j = 0; j < 256; j++) {
            double p[2] = {0.5 + i * u, 0.5 + j * u};
            int ex = bi_sign(ref_orient2d(p, q, r, 53));
            assert_int_equal(sgn(geom_orient2d(p, q, r)), ex);
            assert_int_equal(sgn(geom_orient2d(q, r, p)), ex);
            assert_int_equal(sgn(geom_orient2d(r, p, q)), ex);
            assert_int_equal(sgn(geom_orient2d(q, p, r)), -ex);
            if (sgn(naive_orient2d(p, q, r)) != ex)
                naive_wrong++;
            n++;
            if ((i * 256 + j) % 7 == 0) {
                for (int s = -1; s <= 1; s += 2) {
                    double k = s > 0 ? 0x1p960 : 0x1p-1000;
                    double ps[2] = {p[0] * k, p[1] * k}, qs[2] = {q[0] * k, q[1] * k},
                           rs[2] = {r[0] * k, r[1] * k};
                    assert_int_equal(sgn(geom_orient2d(ps, qs, rs)), ex);
                    assert_int_equal(sgn(geom_orient2d_exact(ps, qs, rs)), ex);
                }
            }
        }
    }
    print_message("orient2d grid: naive formula wrong on %d of %d points\n", naive_wrong, n);
    assert_true(naive_wrong > 100);
}

/* The same idea in 3D: d = (0.5 + i u, 0.5 + j u, 0.5) against the plane
 * z = (x + y) / 2 through (12,12,12), (24,24,24), (12,24,18). */
static void test_orient3d_near_degenerate(void **state)
{
    (void)state;
    const double u = 0x1p-53;
    const double a[3] = {12, 12, 12}, b[3] = {24, 24, 24}, c[3] = {12, 24, 18};
    int naive_wrong = 0, n = 0;
    for (int i = 0; i < 128; i++) {
        for (int j = 0; j < 128; j++) {
            double d[3] = {0.5 + i * u, 0.5 + j * u, 0.5};
            bi r = ref_orient3d(a, b, c, d, 53);
            int ex = bi_sign(r);
            assert_int_equal(sgn(geom_orient3d(a, b, c, d)), ex);
            assert_int_equal(sgn(geom_orient3d(b, a, c, d)), -ex);
            assert_int_equal(sgn(geom_orient3d(b, c, a, d)), ex);
            assert_int_equal(sgn(geom_orient3d(d, b, c, a)), -ex);
            /* the rounded exact value: exact dyadic, so within 1/2 ulp */
            assert_true(geom_orient3d_exact(a, b, c, d) == bi_to_double(r, -3 * 53));
            if (sgn(naive_orient3d(a, b, c, d)) != ex)
                naive_wrong++;
            n++;
        }
    }
    print_message("orient3d grid: naive formula wrong on %d of %d points\n", naive_wrong, n);
    assert_true(naive_wrong > 100);
}

/* Points d = (13 + i u, 13 + j u) near the circle through (12, 12),
 * (14, 12), (12, 14) (which passes through (14, 14) and (13 +- sqrt 2, 13)). */
static void test_incircle_near_degenerate(void **state)
{
    (void)state;
    const double u = 0x1p-49;
    const double a[2] = {12, 12}, b[2] = {14, 12}, c[2] = {12, 14};
    int naive_wrong = 0, n = 0;
    for (int i = -64; i < 64; i++) {
        for (int j = -64; j < 64; j++) {
            double d[2] = {14 + i * u, 14 + j * u};
            int ex = bi_sign(ref_incircle(a, b, c, d, 49));
            assert_int_equal(sgn(geom_incircle(a, b, c, d)), ex);
            assert_int_equal(sgn(geom_incircle(b, c, a, d)), ex);
            assert_int_equal(sgn(geom_incircle(b, a, c, d)), -ex);
            if (sgn(naive_incircle(a, b, c, d)) != ex)
                naive_wrong++;
            n++;
        }
    }
    print_message("incircle grid: naive formula wrong on %d of %d points\n", naive_wrong, n);
    assert_true(naive_wrong > 0);
}

/* Random dyadic input with 40-bit significands and mixed exponents: the
 * _exact values are the correctly rounded exact determinants (within the
 * documented 2^-52 relative error; we check within 1 ulp). */
static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint64_t rng(void)
{
    return test_xorshift64(&rng_state);
}

static double rnd_dyadic(void)
{
    /* k * 2^-s with |k| < 2^40, s in [0, 20]: an integer in units of 2^-20 */
    double k = (double)(int64_t)(rng() >> 24) - 0x1p39;
    return ldexp(k, -(int)(rng() % 21));
}

static void test_exact_values(void **state)
{
    (void)state;
    for (int it = 0; it < 20000; it++) {
        double v[12];
        for (int i = 0; i < 12; i++)
            v[i] = rnd_dyadic();
        if (it % 3 == 0) { /* nearly collinear / coplanar: c = a + (b - a) * t */
            double t = ldexp((double)(rng() % 1024), -10);
            v[4] = v[0] + (v[2] - v[0]) * t;
            v[5] = v[1] + (v[3] - v[1]) * t;
            v[9] = v[0] + (v[3] - v[0]) * t;
            v[10] = v[1] + (v[4] - v[1]) * t;
            v[11] = v[2] + (v[5] - v[2]) * t;
            for (int i = 0; i < 12; i++) /* keep them on the 2^-20 grid */
                v[i] = ldexp(nearbyint(ldexp(v[i], 20)), -20);
        }
        bi r2 = ref_orient2d(v, v + 2, v + 4, 20);
        double x2 = geom_orient2d_exact(v, v + 2, v + 4);
        double e2 = bi_to_double(r2, -40);
        assert_int_equal(sgn(geom_orient2d(v, v + 2, v + 4)), bi_sign(r2));
        assert_true(fabs(x2 - e2) <= ldexp(DBL_EPSILON, ilogb(e2 == 0 ? 1 : e2)));
        assert_int_equal(sgn(x2), bi_sign(r2));

        bi r3 = ref_orient3d(v, v + 3, v + 6, v + 9, 20);
        double x3 = geom_orient3d_exact(v, v + 3, v + 6, v + 9);
        double e3 = bi_to_double(r3, -60);
        assert_int_equal(sgn(geom_orient3d(v, v + 3, v + 6, v + 9)), bi_sign(r3));
        assert_true(fabs(x3 - e3) <= ldexp(DBL_EPSILON, ilogb(e3 == 0 ? 1 : e3)));
        assert_int_equal(sgn(x3), bi_sign(r3));

        bi ri = ref_incircle(v, v + 2, v + 4, v + 6, 20);
        assert_int_equal(sgn(geom_incircle(v, v + 2, v + 4, v + 6)), bi_sign(ri));
    }
}

static void test_nonfinite(void **state)
{
    (void)state;
    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int k = 0; k < 3; k++) {
        for (int pos = 0; pos < 12; pos++) {
            double v[12] = {0, 0, 1, 0, 0, 1, 0.25, 0.25, 1, 1, 1, 0.5};
            v[pos] = bad[k];
            if (pos < 6) {
                assert_true(isnan(geom_orient2d(v, v + 2, v + 4)));
                assert_true(isnan(geom_orient2d_exact(v, v + 2, v + 4)));
            }
            if (pos < 8)
                assert_true(isnan(geom_incircle(v, v + 2, v + 4, v + 6)));
            assert_true(isnan(geom_orient3d(v, v + 3, v + 6, v + 9)));
            assert_true(isnan(geom_orient3d_exact(v, v + 3, v + 6, v + 9)));
        }
    }
    /* collinear-looking input with an infinity must not be reported as 0 */
    const double a[2] = {INFINITY, 0}, b[2] = {0, 0}, c[2] = {1, 0};
    assert_true(isnan(geom_orient2d(a, b, c)));
}

/* Huge and tiny coordinates, and input spanning the whole exponent range,
 * with answers known by construction. */
static void test_extreme_range(void **state)
{
    (void)state;
    /* The products overflow a double: the sign is still right. */
    const double a[2] = {-0x1p1000, -0x1p1000}, b[2] = {0x1p1000, -0x1p1000},
                 c[2] = {0x1p1000, 0x1p1000};
    assert_true(geom_orient2d(a, b, c) > 0.0);
    assert_true(geom_orient2d(a, c, b) < 0.0);
    assert_true(geom_orient2d_exact(a, b, c) == INFINITY);
    /* The products underflow: the sign is kept, never rounded to 0. */
    const double ta[2] = {0, 0}, tb[2] = {0x1p-600, 0}, tc[2] = {0, 0x1p-600};
    assert_true(geom_orient2d(ta, tb, tc) > 0.0);
    assert_true(geom_orient2d(ta, tc, tb) < 0.0);
    assert_true(geom_orient2d_exact(ta, tb, tc) == DBL_TRUE_MIN);
    const double t3[4][3] = {{0, 0, 0}, {0x1p-400, 0, 0}, {0, 0x1p-400, 0}, {0, 0, -0x1p-400}};
    assert_true(geom_orient3d(t3[0], t3[1], t3[2], t3[3]) > 0.0);
    assert_true(geom_orient3d(t3[0], t3[2], t3[1], t3[3]) < 0.0);
    const double h3[4][3] = {{0, 0, 0}, {0x1p400, 0, 0}, {0, 0x1p400, 0}, {0, 0, -0x1p400}};
    assert_true(geom_orient3d(h3[0], h3[1], h3[2], h3[3]) > 0.0);
    assert_true(geom_orient3d_exact(h3[0], h3[1], h3[2], h3[3]) == INFINITY);
    /* Within the double range: 2^-600 * 2^-600 * 2^1000 = 2^-200 exactly. */
    const double m3[4][3] = {{0, 0, 0}, {0x1p-600, 0, 0}, {0, 0x1p-600, 0}, {0, 0, -0x1p1000}};
    assert_true(geom_orient3d_exact(m3[0], m3[1], m3[2], m3[3]) == 0x1p-200);
    assert_true(geom_orient3d(m3[0], m3[1], m3[2], m3[3]) > 0.0);

    /* Points t (2^900, 2^-900) for t = 1, 2, 3 are exactly collinear; moving
     * the third by one ulp of its y makes the determinant exactly 2^-51
     * (x: 2^901 (2^-900 + 2^-951) - (2^-899 + 2^-951) 2^900). This spans
     * 2^1850 and needs the big-number fallback. */
    const double w1[2] = {0x1p900, 0x1p-900}, w2[2] = {0x1p901, 0x1p-899};
    const double w3[2] = {3 * 0x1p900, 3 * 0x1p-900};
    const double w4[2] = {3 * 0x1p900, 3 * 0x1p-900 + 0x1p-951};
    assert_true(geom_orient2d(w1, w2, w3) == 0.0);
    assert_true(geom_orient2d_exact(w1, w2, w3) == 0.0);
    assert_true(geom_orient2d_exact(w1, w2, w4) == 0x1p-51);
    assert_true(geom_orient2d(w1, w4, w2) < 0.0);
    /* Subnormal coordinates mixed with huge ones. */
    const double s1[2] = {DBL_TRUE_MIN, 0}, s2[2] = {0, DBL_TRUE_MIN}, s3[2] = {0, 0};
    assert_true(geom_orient2d(s1, s2, s3) > 0.0);
    const double s4[2] = {0x1p1023, 0x1p1023};
    const double s5[2] = {0x1p1023, 0x1p1023 - 0x1p970}; /* one ulp below */
    const double s6[2] = {DBL_TRUE_MIN, DBL_TRUE_MIN};
    /* (s4 - s6) x (s5 - s6): both rows ~(2^1023, 2^1023); exact sign from
     * the reference-free identity det = -(2^1023 - m)(2^970), m = 2^-1074 */
    assert_true(geom_orient2d(s4, s5, s6) < 0.0);
    assert_true(geom_orient2d(s5, s4, s6) > 0.0);
    /* Scaled incircle: the grid answer is invariant under 2^k scaling. */
    const double ia[2] = {12 * 0x1p-500, 12 * 0x1p-500}, ib[2] = {14 * 0x1p-500, 12 * 0x1p-500},
                 ic[2] = {12 * 0x1p-500, 14 * 0x1p-500};
    const double id_on[2] = {14 * 0x1p-500, 14 * 0x1p-500};
    const double id_in[2] = {(14 - 0x1p-49) * 0x1p-500, 14 * 0x1p-500};
    assert_true(geom_incircle(ia, ib, ic, id_on) == 0.0);
    assert_true(geom_incircle(ia, ib, ic, id_in) > 0.0);
}

/* geom_predicate_many: bitwise the single predicates on random, nearly
 * degenerate, 1e8-offset and non-finite rows, one point per row and one
 * point shared by every row (stride 0). */
static void test_predicate_many(void **state)
{
    (void)state;
    enum { M = 3000 };
    static double pts[4][3 * M], out[M];
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 3 * M; i++)
            pts[j][i] = rnd_dyadic();
    for (int i = 0; i < M; i += 3) { /* nearly collinear / coplanar rows */
        double t = ldexp((double)(rng() % 1024), -10);
        for (int k = 0; k < 3; k++)
            pts[2][3 * i + k] = pts[0][3 * i + k] + (pts[1][3 * i + k] - pts[0][3 * i + k]) * t;
    }
    for (int i = 1; i < M; i += 7) /* 1e8 offsets with tiny spread */
        for (int j = 0; j < 4; j++)
            for (int k = 0; k < 3; k++)
                pts[j][3 * i + k] = 1e8 + ldexp((double)(rng() % 8), -26);
    pts[1][3 * 5] = NAN;
    pts[3][3 * 11 + 1] = INFINITY;
    pts[0][3 * 17 + 2] = -INFINITY;
    for (int kind = GEOM_PREDICATE_ORIENT2D; kind <= GEOM_PREDICATE_ORIENT3D_EXACT; kind++) {
        size_t dim = (kind == GEOM_PREDICATE_ORIENT3D || kind == GEOM_PREDICATE_ORIENT3D_EXACT)
                         ? 3 : 2;
        for (int shared = 0; shared < 2; shared++) {
            const double *p[4] = {pts[0], pts[1], pts[2], pts[3]};
            size_t st[4] = {dim, dim, dim, dim};
            if (shared) /* the first two points in every row */
                st[0] = st[1] = 0;
            assert_int_equal(geom_predicate_many((geom_predicate)kind, M, p, st, out), GEOM_OK);
            for (size_t i = 0; i < M; i++) {
                const double *a = p[0] + i * st[0], *b = p[1] + i * st[1],
                             *c = p[2] + i * st[2], *d = p[3] + i * st[3];
                double want;
                switch (kind) {
                case GEOM_PREDICATE_ORIENT2D: want = geom_orient2d(a, b, c); break;
                case GEOM_PREDICATE_ORIENT3D: want = geom_orient3d(a, b, c, d); break;
                case GEOM_PREDICATE_INCIRCLE: want = geom_incircle(a, b, c, d); break;
                case GEOM_PREDICATE_ORIENT2D_EXACT: want = geom_orient2d_exact(a, b, c); break;
                default: want = geom_orient3d_exact(a, b, c, d); break;
                }
                assert_true(same_bits_or_nan(out[i], want));
            }
        }
    }
    /* a NaN row is NaN (pts[1][15] is row 7's y with 2D strides) */
    const double *p[4] = {pts[0], pts[1], pts[2], pts[3]};
    const size_t st[4] = {2, 2, 2, 2};
    assert_int_equal(geom_predicate_many(GEOM_PREDICATE_ORIENT2D, M, p, st, out), GEOM_OK);
    assert_true(isnan(out[7]) && !isnan(out[6]) && !isnan(out[8]));
    /* bad arguments: nothing written */
    out[0] = 7.0;
    const double *bad[4] = {pts[0], NULL, pts[2], pts[3]};
    assert_int_equal(geom_predicate_many(GEOM_PREDICATE_ORIENT2D, 1, bad, st, out),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_predicate_many((geom_predicate)0, 1, p, st, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_predicate_many((geom_predicate)6, 1, p, st, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_predicate_many(GEOM_PREDICATE_ORIENT2D, 1, NULL, st, out),
                     GEOM_ERR_INVALID_ARG);
    assert_true(out[0] == 7.0);
    assert_int_equal(geom_predicate_many(GEOM_PREDICATE_ORIENT2D, 0, NULL, NULL, NULL), GEOM_OK);
    /* pts[3] is ignored by the 3-point predicates only */
    const double *three[4] = {pts[0], pts[1], pts[2], NULL};
    assert_int_equal(geom_predicate_many(GEOM_PREDICATE_ORIENT2D, 2, three, st, out), GEOM_OK);
    assert_int_equal(geom_predicate_many(GEOM_PREDICATE_INCIRCLE, 2, three, st, out),
                     GEOM_ERR_INVALID_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_closed_forms),
        cmocka_unit_test(test_integer_grid),
        cmocka_unit_test(test_orient2d_near_degenerate),
        cmocka_unit_test(test_orient3d_near_degenerate),
        cmocka_unit_test(test_incircle_near_degenerate),
        cmocka_unit_test(test_exact_values),
        cmocka_unit_test(test_nonfinite),
        cmocka_unit_test(test_extreme_range),
        cmocka_unit_test(test_predicate_many),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
