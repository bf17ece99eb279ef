/*
 * Exact arithmetic for the predicates and the barycentric module: floating-
 * point expansions (Shewchuk 1997: Fast-Expansion-Sum and Scale-Expansion
 * with zero elimination, Compress), power-of-two input scaling that keeps
 * every expansion component in the normal range, and a small arbitrary-
 * precision binary fallback ("big float": sign, 32-bit limbs, binary
 * exponent) for input whose dynamic range no scaling can accommodate.
 * See expansion.h.
 */
#include "core/expansion.h"

#include <limits.h>
#include <stdint.h>
#include <string.h>

/* ------------------------------------------------------------ expansions */

/* x + y == a * b exactly, b already split into bh + bl. */
static inline void two_product_presplit(double a, double b, double bh, double bl, double *x,
                                        double *y)
{
    double p = a * b;
    double ah, al;
    geom__split(a, &ah, &al);
    double e1 = p - ah * bh;
    double e2 = e1 - al * bh;
    double e3 = e2 - ah * bl;
    *x = p;
    *y = al * bl - e3;
}

int geom__xp_sum(int elen, const double *e, int flen, const double *f, double *h)
{
    /* Merge the components by increasing magnitude, then sweep a running
     * approximation Q through them, emitting the exact round-off of each
     * addition (Fast-Expansion-Sum, Shewchuk 1997, Theorem 13). */
    int i = 0, j = 0, k = 0;
    int total = elen + flen;
    double q, g, qn, hh;
#define GEOM_XP_NEXT(out)                                                    \
    do {                                                                     \
        if (j >= flen || (i < elen && fabs(e[i]) < fabs(f[j])))              \
            (out) = e[i++];                                                  \
        else                                                                 \
            (out) = f[j++];                                                  \
    } while (0)
    if (total == 0) {
        h[0] = 0.0;
        return 1;
    }
    GEOM_XP_NEXT(q);
    if (total >= 2) {
        GEOM_XP_NEXT(g);
        geom__fast_two_sum(g, q, &qn, &hh);
        q = qn;
        if (hh != 0.0)
            h[k++] = hh;
        for (int n = 2; n < total; n++) {
            GEOM_XP_NEXT(g);
            geom__two_sum(q, g, &qn, &hh);
            q = qn;
            if (hh != 0.0)
                h[k++] = hh;
        }
    }
#undef GEOM_XP_NEXT
    if (q != 0.0 || k == 0)
        h[k++] = q;
    return k;
}

int geom__xp_scale(int elen, const double *e, double b, double *h)
{
    /* Scale-Expansion (Shewchuk 1997, Theorem 19) with zero elimination. */
    double bh, bl, q, hh, p1, p0, s;
    int k = 0;
    geom__split(b, &bh, &bl);
    two_product_presplit(e[0], b, bh, bl, &q, &hh);
    if (hh != 0.0)
        h[k++] = hh;
    for (int i = 1; i < elen; i++) {
        two_product_presplit(e[i], b, bh, bl, &p1, &p0);
        geom__two_sum(q, p0, &s, &hh);
        if (hh != 0.0)
            h[k++] = hh;
        geom__fast_two_sum(p1, s, &q, &hh);
        if (hh != 0.0)
            h[k++] = hh;
    }
    if (q != 0.0 || k == 0)
        h[k++] = q;
    return k;
}

int geom__xp_mul(int elen, const double *e, int flen, const double *f, double *h,
                     double *work)
{
    /* Sum of the partial products e[i] * f; the accumulator alternates
     * between h and the work buffer so that it ends in h. */
    double *tmp = work;
    double *buf = work + 2 * flen;
    double *cur = (elen % 2 == 1) ? h : buf;
    int len = geom__xp_scale(flen, f, e[0], cur);
    for (int i = 1; i < elen; i++) {
        int tlen = geom__xp_scale(flen, f, e[i], tmp);
        double *dst = (cur == h) ? buf : h;
        len = geom__xp_sum(len, cur, tlen, tmp, dst);
        cur = dst;
    }
    return len;
}

void geom__xp_negate(int elen, double *e)
{
    for (int i = 0; i < elen; i++)
        e[i] = -e[i];
}

int geom__xp_diff(double a, double b, double h[2])
{
    double x, y;
    geom__two_diff(a, b, &x, &y);
    if (y == 0.0) {
        h[0] = x;
        return 1;
    }
    h[0] = y;
    h[1] = x;
    return 2;
}

int geom__xp_compress(int elen, double *e)
{
    /* Compress (Shewchuk 1997, Section 2.8). */
    int bottom = elen - 1;
    double q = e[bottom], qn, r;
    for (int i = elen - 2; i >= 0; i--) {
        geom__fast_two_sum(q, e[i], &qn, &r);
        if (r != 0.0) {
            e[bottom--] = qn;
            q = r;
        } else {
            q = qn;
        }
    }
    int top = 0;
    for (int i = bottom + 1; i < elen; i++) {
        geom__fast_two_sum(e[i], q, &qn, &r);
        if (r != 0.0)
            e[top++] = r;
        q = qn;
    }
    e[top] = q;
    return top + 1;
}

double geom__xp_approx(int elen, double *e)
{
    int m = geom__xp_compress(elen, e);
    if (m == 1)
        return e[0];
    return e[m - 1] + e[m - 2];
}

/* --------------------------------------------------------------- scaling */

enum { XP_ZERO, XP_DIRECT, XP_WIDE };

/* Plan the evaluation of a polynomial of degree `deg` (2, 3 or 4) in
 * differences of the n values v. With every scaled value below 2^T (T =
 * floor(992 / deg)), every sum of products stays below 2^1000; with every
 * scaled value a multiple of 2^L (L = ceil(-1000 / deg)), every product and
 * every round-off term is a multiple of 2^-1000, so nothing underflows and
 * all error-free transformations are exact. Returns XP_ZERO when all values
 * are zero, XP_DIRECT with *shift (0 when no scaling is needed), or XP_WIDE
 * when the values span too many binades for any scaling. */
static int xp_plan(double *v, int n, int deg, int *shift)
{
    static const int T[5] = {0, 0, 496, 330, 248};
    static const int L[5] = {0, 0, -500, -333, -250};
    /* 2^T and 2^(L + 52) */
    static const double HI[5] = {0.0, 0.0, 0x1p496, 0x1p330, 0x1p248};
    static const double LO[5] = {0.0, 0.0, 0x1p-448, 0x1p-281, 0x1p-198};
    const double hi = HI[deg], lo = LO[deg];
    int direct = 1, any = 0;
    for (int i = 0; i < n; i++) {
        double a = fabs(v[i]);
        if (a != 0.0) {
            any = 1;
            if (!(a >= lo && a < hi))
                direct = 0;
        }
    }
    *shift = 0;
    if (!any)
        return XP_ZERO;
    if (direct)
        return XP_DIRECT;
    int emax = INT_MIN, umin = INT_MAX;
    for (int i = 0; i < n; i++) {
        if (v[i] != 0.0) {
            int ex;
            (void)frexp(v[i], &ex); /* |v| in [2^(ex-1), 2^ex) */
            int u = ex - 53 < -1074 ? -1074 : ex - 53; /* exponent of ulp(v) */
            if (ex > emax)
                emax = ex;
            if (u < umin)
                umin = u;
        }
    }
    int s = T[deg] - emax;
    if (umin + s < L[deg])
        return XP_WIDE;
    for (int i = 0; i < n; i++)
        v[i] = ldexp(v[i], s);
    *shift = s;
    return XP_DIRECT;
}

/* The xval of r * 2^k. */
static geom__xval xval_shifted(double r, int k)
{
    geom__xval v = geom__xval_from_double(r);
    if (v.m != 0.0)
        v.e += k;
    return v;
}

/* ------------------------------------------------------------- big float */

/* Worst case: a degree-4 polynomial in doubles is a multiple of 2^(-4*1074)
 * below 2^(4*1025+8), i.e. at most 8404 significant bits = 263 limbs. */
#define BF_LIMBS 272

typedef struct bf {
    int neg;  /* sign, 1 if negative */
    int n;    /* limbs in use; 0 for zero */
    int exp;  /* value = (-1)^neg * sum d[i] 2^(32 i) * 2^exp */
    uint32_t d[BF_LIMBS];
} bf;

static void bf_zero(bf *x)
{
    x->neg = 0;
    x->n = 0;
    x->exp = 0;
}

/* Drop high zero limbs and move low zero limbs into the exponent. */
static void bf_trim(bf *x)
{
    while (x->n > 0 && x->d[x->n - 1] == 0)
        x->n--;
    if (x->n == 0) {
        bf_zero(x);
        return;
    }
    int z = 0;
    while (x->d[z] == 0)
        z++;
    if (z > 0) {
        memmove(x->d, x->d + z, (size_t)(x->n - z) * sizeof x->d[0]);
        x->n -= z;
        x->exp += 32 * z;
    }
}

static void bf_set(bf *x, double v)
{
    if (v == 0.0) {
        bf_zero(x);
        return;
    }
    int e;
    double m = frexp(fabs(v), &e);
    uint64_t im = (uint64_t)ldexp(m, 53); /* exact: 53-bit integer */
    x->neg = v < 0.0;
    x->exp = e - 53;
    x->d[0] = (uint32_t)im;
    x->d[1] = (uint32_t)(im >> 32);
    x->n = 2;
    bf_trim(x);
}

/* dst = src << bits; returns the length (high zero limbs trimmed), or -1 if
 * it would not fit (unreachable for the polynomials evaluated here). */
static int mag_shl(const uint32_t *src, int n, int bits, uint32_t *dst)
{
    int limbs = bits / 32, b = bits % 32;
    if (limbs + n + 1 > BF_LIMBS)
        return -1;
    for (int i = 0; i < limbs; i++)
        dst[i] = 0;
    int len;
    if (b == 0) {
        for (int i = 0; i < n; i++)
            dst[limbs + i] = src[i];
        len = limbs + n;
    } else {
        uint32_t carry = 0;
        for (int i = 0; i < n; i++) {
            dst[limbs + i] = (src[i] << b) | carry;
            carry = src[i] >> (32 - b);
        }
        dst[limbs + n] = carry;
        len = limbs + n + 1;
    }
    while (len > 0 && dst[len - 1] == 0)
        len--;
    return len;
}

static int mag_cmp(const uint32_t *a, int an, const uint32_t *b, int bn)
{
    if (an != bn)
        return an < bn ? -1 : 1;
    for (int i = an - 1; i >= 0; i--)
        if (a[i] != b[i])
            return a[i] < b[i] ? -1 : 1;
    return 0;
}

static int mag_add(const uint32_t *a, int an, const uint32_t *b, int bn, uint32_t *r)
{
    if (an < bn) {
        const uint32_t *t = a;
        a = b;
        b = t;
        int tn = an;
        an = bn;
        bn = tn;
    }
    uint64_t carry = 0;
    for (int i = 0; i < an; i++) {
        uint64_t s = (uint64_t)a[i] + (i < bn ? b[i] : 0) + carry;
        r[i] = (uint32_t)s;
        carry = s >> 32;
    }
    if (carry && an < BF_LIMBS)
        r[an++] = (uint32_t)carry;
    return an;
}

/* r = a - b with a >= b. */
static int mag_sub(const uint32_t *a, int an, const uint32_t *b, int bn, uint32_t *r)
{
    int64_t borrow = 0;
    for (int i = 0; i < an; i++) {
        int64_t s = (int64_t)a[i] - (i < bn ? (int64_t)b[i] : 0) - borrow;
        borrow = s < 0;
        r[i] = (uint32_t)(s + (borrow << 32));
    }
    while (an > 0 && r[an - 1] == 0)
        an--;
    return an;
}

/* r = a + (negate_b ? -b : b); r may alias a or b. */
static void bf_addsub(bf *r, const bf *a, const bf *b, int negate_b)
{
    int bneg = b->neg ^ negate_b;
    if (b->n == 0) {
        if (r != a)
            *r = *a;
        return;
    }
    if (a->n == 0) {
        if (r != b)
            *r = *b;
        r->neg = bneg;
        return;
    }
    uint32_t A[BF_LIMBS], B[BF_LIMBS];
    int e = a->exp < b->exp ? a->exp : b->exp;
    int an = mag_shl(a->d, a->n, a->exp - e, A);
    int bn = mag_shl(b->d, b->n, b->exp - e, B);
    if (an < 0 || bn < 0) { /* unreachable: see BF_LIMBS */
        bf_zero(r);
        return;
    }
    int aneg = a->neg;
    if (aneg == bneg) {
        r->n = mag_add(A, an, B, bn, r->d);
        r->neg = aneg;
    } else if (mag_cmp(A, an, B, bn) >= 0) {
        r->n = mag_sub(A, an, B, bn, r->d);
        r->neg = aneg;
    } else {
        r->n = mag_sub(B, bn, A, an, r->d);
        r->neg = bneg;
    }
    r->exp = e;
    bf_trim(r);
}

static void bf_add(bf *r, const bf *a, const bf *b) { bf_addsub(r, a, b, 0); }
static void bf_sub(bf *r, const bf *a, const bf *b) { bf_addsub(r, a, b, 1); }

/* r = a * b; r may alias a or b. */
static void bf_mul(bf *r, const bf *a, const bf *b)
{
    if (a->n == 0 || b->n == 0 || a->n + b->n > BF_LIMBS) { /* the last is unreachable */
        bf_zero(r);
        return;
    }
    uint32_t t[BF_LIMBS];
    int n = a->n + b->n;
    memset(t, 0, (size_t)n * sizeof t[0]);
    for (int i = 0; i < a->n; i++) {
        uint64_t carry = 0;
        for (int j = 0; j < b->n; j++) {
            uint64_t cur = (uint64_t)a->d[i] * b->d[j] + t[i + j] + carry;
            t[i + j] = (uint32_t)cur;
            carry = cur >> 32;
        }
        t[i + b->n] = (uint32_t)carry;
    }
    int neg = a->neg ^ b->neg, exp = a->exp + b->exp;
    memcpy(r->d, t, (size_t)n * sizeof t[0]);
    r->n = n;
    r->neg = neg;
    r->exp = exp;
    bf_trim(r);
}

/* r = x - y for doubles x, y. */
static void bf_diff_d(bf *r, double x, double y)
{
    bf t;
    bf_set(r, x);
    bf_set(&t, y);
    bf_sub(r, r, &t);
}

static uint32_t bf_limb(const bf *x, int i)
{
    return (i >= 0 && i < x->n) ? x->d[i] : 0u;
}

/* Correctly rounded xval of x. */
static geom__xval bf_to_xval(const bf *x)
{
    geom__xval v = {0.0, 0};
    if (x->n == 0)
        return v;
    uint32_t topl = x->d[x->n - 1];
    int bl = 0;
    while (bl < 32 && (topl >> bl) != 0)
        bl++;
    int len = 32 * (x->n - 1) + bl; /* bit length of the magnitude */
    int pos = len - 64;             /* lowest of the top 64 bits */
    int q = pos >= 0 ? pos / 32 : -((-pos + 31) / 32);
    int r = pos - 32 * q;
    uint64_t w = (uint64_t)bf_limb(x, q) | ((uint64_t)bf_limb(x, q + 1) << 32);
    uint64_t t = r == 0 ? w : (w >> r) | ((uint64_t)bf_limb(x, q + 2) << (64 - r));
    /* Sticky bit: anything below the top 64 bits (bit 0 of t lies far
     * below the double's rounding position). */
    int sticky = 0;
    for (int i = 0; i < q && i < x->n && !sticky; i++)
        sticky = x->d[i] != 0;
    if (!sticky && r > 0 && q >= 0)
        sticky = (bf_limb(x, q) & ((1u << r) - 1u)) != 0;
    t |= (uint64_t)sticky;
    double m = (double)t * 0x1p-64; /* in [0.5, 1] */
    int e = x->exp + len;
    if (m == 1.0) {
        m = 0.5;
        e++;
    }
    v.m = x->neg ? -m : m;
    v.e = e;
    return v;
}

/* r = p*q - s*t for big floats. */
static void bf_cross(bf *r, const bf *p, const bf *q, const bf *s, const bf *t)
{
    bf u;
    bf_mul(r, p, q);
    bf_mul(&u, s, t);
    bf_sub(r, r, &u);
}

/* ------------------------------------------------------------ orient2d */

static double xp_orient2d(const double *v)
{
    double acx[2], bcy[2], acy[2], bcx[2], p[8], q[8], det[16], work[12];
    int n1 = geom__xp_diff(v[0], v[4], acx);
    int n2 = geom__xp_diff(v[3], v[5], bcy);
    int n3 = geom__xp_diff(v[1], v[5], acy);
    int n4 = geom__xp_diff(v[2], v[4], bcx);
    int np = geom__xp_mul(n1, acx, n2, bcy, p, work);
    int nq = geom__xp_mul(n3, acy, n4, bcx, q, work);
    geom__xp_negate(nq, q);
    int nd = geom__xp_sum(np, p, nq, q, det);
    return geom__xp_approx(nd, det);
}

static geom__xval bf_orient2d(const double *v)
{
    bf acx, bcy, acy, bcx, r;
    bf_diff_d(&acx, v[0], v[4]);
    bf_diff_d(&bcy, v[3], v[5]);
    bf_diff_d(&acy, v[1], v[5]);
    bf_diff_d(&bcx, v[2], v[4]);
    bf_cross(&r, &acx, &bcy, &acy, &bcx);
    return bf_to_xval(&r);
}

geom__xval geom__xeval_orient2d(const double a[2], const double b[2], const double c[2])
{
    double v[6] = {a[0], a[1], b[0], b[1], c[0], c[1]};
    int shift;
    switch (xp_plan(v, 6, 2, &shift)) {
    case XP_ZERO: return xval_shifted(0.0, 0);
    case XP_WIDE: return bf_orient2d(v);
    default: break;
    }
    return xval_shifted(xp_orient2d(v), -2 * shift);
}

/* ------------------------------------------------------------ orient3d */

/* h = p*q - s*t for 2-component expansions; h holds 16. */
static int xp_cross2(int pn, const double *p, int qn, const double *q, int sn, const double *s,
                     int tn, const double *t, double *h)
{
    double x[8], y[8], work[12];
    int nx = geom__xp_mul(pn, p, qn, q, x, work);
    int ny = geom__xp_mul(sn, s, tn, t, y, work);
    geom__xp_negate(ny, y);
    /* Compressing keeps the later products small: the value of a degree-2
     * polynomial rarely needs more than three components. */
    return geom__xp_compress(geom__xp_sum(nx, x, ny, y, h), h);
}

static double xp_orient3d(const double *v)
{
    /* v: a (0..2), b (3..5), c (6..8), d (9..11) */
    double ad[3][2], bd[3][2], cd[3][2];
    int an[3], bn[3], cn[3];
    for (int k = 0; k < 3; k++) {
        an[k] = geom__xp_diff(v[k], v[9 + k], ad[k]);
        bn[k] = geom__xp_diff(v[3 + k], v[9 + k], bd[k]);
        cn[k] = geom__xp_diff(v[6 + k], v[9 + k], cd[k]);
    }
    double m[16], ta[64], tb[64], tc[64], s1[128], det[192], work[96];
    /* adz (bdx cdy - bdy cdx) + bdz (cdx ady - cdy adx) + cdz (adx bdy - ady bdx) */
    int nm = xp_cross2(bn[0], bd[0], cn[1], cd[1], bn[1], bd[1], cn[0], cd[0], m);
    int na = geom__xp_mul(an[2], ad[2], nm, m, ta, work);
    nm = xp_cross2(cn[0], cd[0], an[1], ad[1], cn[1], cd[1], an[0], ad[0], m);
    int nb = geom__xp_mul(bn[2], bd[2], nm, m, tb, work);
    nm = xp_cross2(an[0], ad[0], bn[1], bd[1], an[1], ad[1], bn[0], bd[0], m);
    int nc = geom__xp_mul(cn[2], cd[2], nm, m, tc, work);
    int n1 = geom__xp_sum(na, ta, nb, tb, s1);
    int nd = geom__xp_sum(n1, s1, nc, tc, det);
    return geom__xp_approx(nd, det);
}

static geom__xval bf_orient3d(const double *v)
{
    bf ad[3], bd[3], cd[3], m, t, r;
    for (int k = 0; k < 3; k++) {
        bf_diff_d(&ad[k], v[k], v[9 + k]);
        bf_diff_d(&bd[k], v[3 + k], v[9 + k]);
        bf_diff_d(&cd[k], v[6 + k], v[9 + k]);
    }
    bf_cross(&m, &bd[0], &cd[1], &bd[1], &cd[0]);
    bf_mul(&r, &ad[2], &m);
    bf_cross(&m, &cd[0], &ad[1], &cd[1], &ad[0]);
    bf_mul(&t, &bd[2], &m);
    bf_add(&r, &r, &t);
    bf_cross(&m, &ad[0], &bd[1], &ad[1], &bd[0]);
    bf_mul(&t, &cd[2], &m);
    bf_add(&r, &r, &t);
    return bf_to_xval(&r);
}

geom__xval geom__xeval_orient3d(const double a[3], const double b[3], const double c[3],
                                   const double d[3])
{
    double v[12] = {a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2]};
    int shift;
    switch (xp_plan(v, 12, 3, &shift)) {
    case XP_ZERO: return xval_shifted(0.0, 0);
    case XP_WIDE: return bf_orient3d(v);
    default: break;
    }
    return xval_shifted(xp_orient3d(v), -3 * shift);
}

/* ------------------------------------------------------------ incircle */

/* Buffers for a sum of three products of 16-component expansions. */
typedef struct xp_dot3_buf {
    double x[512], y[512], s1[1024], out[1536], work[544];
} xp_dot3_buf;

/* sum_k p[k] * q[k] for three pairs of expansions of at most 16 components;
 * the result is left in buf->out, its length returned. */
static int xp_dot3(const int pn[3], double p[3][16], const int qn[3], double q[3][16],
                   xp_dot3_buf *buf)
{
    int nx = geom__xp_mul(pn[0], p[0], qn[0], q[0], buf->x, buf->work);
    int ny = geom__xp_mul(pn[1], p[1], qn[1], q[1], buf->y, buf->work);
    int n1 = geom__xp_sum(nx, buf->x, ny, buf->y, buf->s1);
    nx = geom__xp_mul(pn[2], p[2], qn[2], q[2], buf->x, buf->work);
    return geom__xp_sum(n1, buf->s1, nx, buf->x, buf->out);
}

static double xp_incircle(const double *v)
{
    /* v: a (0,1), b (2,3), c (4,5), d (6,7) */
    double dx[3][2], dy[3][2];
    int nx[3], ny[3];
    for (int k = 0; k < 3; k++) {
        nx[k] = geom__xp_diff(v[2 * k], v[6], dx[k]);
        ny[k] = geom__xp_diff(v[2 * k + 1], v[7], dy[k]);
    }
    double lift[3][16], cross[3][16], sq1[8], sq2[8], work[12];
    int nl[3], nc[3];
    for (int k = 0; k < 3; k++) {
        int n1 = geom__xp_mul(nx[k], dx[k], nx[k], dx[k], sq1, work);
        int n2 = geom__xp_mul(ny[k], dy[k], ny[k], dy[k], sq2, work);
        nl[k] = geom__xp_compress(geom__xp_sum(n1, sq1, n2, sq2, lift[k]), lift[k]);
        int i = (k + 1) % 3, j = (k + 2) % 3;
        /* the cofactor of lift k: di_x dj_y - di_y dj_x */
        nc[k] = xp_cross2(nx[i], dx[i], ny[j], dy[j], ny[i], dy[i], nx[j], dx[j], cross[k]);
    }
    xp_dot3_buf buf;
    int n = xp_dot3(nl, lift, nc, cross, &buf);
    return geom__xp_approx(n, buf.out);
}

static geom__xval bf_incircle(const double *v)
{
    bf dx[3], dy[3], lift, cross, t, r;
    for (int k = 0; k < 3; k++) {
        bf_diff_d(&dx[k], v[2 * k], v[6]);
        bf_diff_d(&dy[k], v[2 * k + 1], v[7]);
    }
    bf_zero(&r);
    for (int k = 0; k < 3; k++) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        bf_mul(&lift, &dx[k], &dx[k]);
        bf_mul(&t, &dy[k], &dy[k]);
        bf_add(&lift, &lift, &t);
        bf_cross(&cross, &dx[i], &dy[j], &dy[i], &dx[j]);
        bf_mul(&t, &lift, &cross);
        bf_add(&r, &r, &t);
    }
    return bf_to_xval(&r);
}

geom__xval geom__xeval_incircle(const double a[2], const double b[2], const double c[2],
                                   const double d[2])
{
    double v[8] = {a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1]};
    int shift;
    switch (xp_plan(v, 8, 4, &shift)) {
    case XP_ZERO: return xval_shifted(0.0, 0);
    case XP_WIDE: return bf_incircle(v);
    default: break;
    }
    return xval_shifted(xp_incircle(v), -4 * shift);
}

/* ---------------------------------------------------- 3D barycentrics */

/* n = (q - p) x (r - p) as three expansions (16 components each). */
static void xp_normal(const double *p, const double *q, const double *r, double n[3][16],
                      int nn[3])
{
    double u[3][2], w[3][2];
    int un[3], wn[3];
    for (int k = 0; k < 3; k++) {
        un[k] = geom__xp_diff(q[k], p[k], u[k]);
        wn[k] = geom__xp_diff(r[k], p[k], w[k]);
    }
    for (int k = 0; k < 3; k++) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        nn[k] = xp_cross2(un[i], u[i], wn[j], w[j], un[j], u[j], wn[i], w[i], n[k]);
    }
}

static void bf_normal(const double *p, const double *q, const double *r, bf n[3])
{
    bf u[3], w[3];
    for (int k = 0; k < 3; k++) {
        bf_diff_d(&u[k], q[k], p[k]);
        bf_diff_d(&w[k], r[k], p[k]);
    }
    for (int k = 0; k < 3; k++) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        bf_cross(&n[k], &u[i], &w[j], &u[j], &w[i]);
    }
}

static geom__xval bf_dot3(const bf x[3], const bf y[3])
{
    bf r, t;
    bf_mul(&r, &x[0], &y[0]);
    bf_mul(&t, &x[1], &y[1]);
    bf_add(&r, &r, &t);
    bf_mul(&t, &x[2], &y[2]);
    bf_add(&r, &r, &t);
    return bf_to_xval(&r);
}

void geom__xeval_tri3(const double a[3], const double b[3], const double c[3],
                          const double p[3], unsigned mask, geom__xval num[3], geom__xval *den)
{
    double v[12] = {a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], p[0], p[1], p[2]};
    const double *va = v, *vb = v + 3, *vc = v + 6, *vp = v + 9;
    /* sub-triangle i: (c-b) x (p-b), (a-c) x (p-c), (b-a) x (p-a) */
    const double *sub[3][2] = {{vb, vc}, {vc, va}, {va, vb}};
    int shift;
    switch (xp_plan(v, 12, 4, &shift)) {
    case XP_ZERO:
        for (int i = 0; i < 3; i++)
            num[i] = xval_shifted(0.0, 0);
        *den = xval_shifted(0.0, 0);
        return;
    case XP_WIDE: {
        bf n[3], m[3];
        bf_normal(va, vb, vc, n);
        if (mask & 8u)
            *den = bf_dot3(n, n);
        for (int i = 0; i < 3; i++) {
            if (mask & (1u << i)) {
                bf_normal(sub[i][0], sub[i][1], vp, m);
                num[i] = bf_dot3(n, m);
            }
        }
        return;
    }
    default: break;
    }
    double n[3][16], m[3][16];
    int nn[3], mn[3], len;
    xp_dot3_buf buf;
    xp_normal(va, vb, vc, n, nn);
    if (mask & 8u) {
        len = xp_dot3(nn, n, nn, n, &buf);
        *den = xval_shifted(geom__xp_approx(len, buf.out), -4 * shift);
    }
    for (int i = 0; i < 3; i++) {
        if (mask & (1u << i)) {
            xp_normal(sub[i][0], sub[i][1], vp, m, mn);
            len = xp_dot3(nn, n, mn, m, &buf);
            num[i] = xval_shifted(geom__xp_approx(len, buf.out), -4 * shift);
        }
    }
}
