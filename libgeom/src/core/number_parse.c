/*
 * Exact decimal-to-double parsing: the Eisel-Lemire algorithm (Daniel
 * Lemire, "Number Parsing at a Gigabyte per Second", Software: Practice and
 * Experience 51(8), 2021; after Michael Eisel's fast_double_parser).
 *
 * The decimal significand w (its first 19 significant digits) is shifted so
 * that its top bit is set and multiplied by a truncated 128-bit significand
 * of 5^q; the top 64 bits of the product give the 53-bit result plus a
 * rounding bit, and a binary exponent follows from q*log2(10). When the bits
 * below the rounding position are all ones, a second multiplication with the
 * low half of 5^q refines the product; if a carry could still reach the
 * kept bits, the algorithm cannot decide. Exact ties (possible only for
 * -4 <= q <= 23) round to even. With more than 19 digits, w and w + 1 bound
 * the value: equal results decide it.
 *
 * Undecided cases go to a correct fallback: the C library's strtod
 * (correctly rounded in glibc) on a bounded, locale-proof copy: at most 780
 * significant digits as an integer with an exponent, plus a sticky "1" when
 * nonzero digits were cut (no halfway point between two doubles has more
 * than 767 significant digits, so the cut never changes the rounding).
 * Small exact cases (w <= 2^53, |q| <= 22) use one exact multiplication or
 * division (Clinger 1990). C99 hexadecimal input ("0x1.8p-3") is rounded
 * directly from its bits.
 */
#include "core/internal.h"
#include "core/numbers_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

__extension__ typedef unsigned __int128 prs_u128;

enum { FALLBACK_DIGITS = 780 };

static const double exact_pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                       1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                       1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

static int is_digit(char ch) { return ch >= '0' && ch <= '9'; }

static double from_bits(uint64_t b)
{
    double v;
    memcpy(&v, &b, sizeof v);
    return v;
}

static int clz64(uint64_t v)
{
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_clzll(v);
#else
    int n = 0;
    while (!(v & (UINT64_C(1) << 63))) {
        v <<= 1;
        n++;
    }
    return n;
#endif
}

#define INF_BITS (UINT64_C(0x7ff) << 52)

/* |w * 10^q| correctly rounded into *bits, w != 0; 0 when decided, -1 when
 * the truncated power of five leaves the rounding open. */
static int eisel_lemire(uint64_t w, int64_t q, uint64_t *bits)
{
    if (q < GEOM__POW5_QMIN) { /* below half the smallest subnormal */
        *bits = 0;
        return 0;
    }
    if (q > 308) {
        *bits = INF_BITS;
        return 0;
    }
    const int lz = clz64(w);
    w <<= lz;
    const uint64_t *t = geom__pow5_128[q - GEOM__POW5_QMIN];
    prs_u128 p = (prs_u128)w * t[0];
    uint64_t hi = (uint64_t)(p >> 64), lo = (uint64_t)p;
    if ((hi & 0x1ff) == 0x1ff) {
        /* the dropped part adds less than 2 units to lo (one from w * t[1]'s
         * low half, one from 5^q's truncation) */
        uint64_t h2 = (uint64_t)(((prs_u128)w * t[1]) >> 64);
        lo += h2;
        hi += lo < h2;
        if ((hi & 0x1ff) == 0x1ff && lo > UINT64_MAX - 2)
            return -1;
    }
    const int upper = (int)(hi >> 63);
    uint64_t mant = hi >> (upper + 9);
    int32_t e2 = (int32_t)(((217706 * q) >> 16) + 63) + upper - lz + 1023;
    if (e2 <= 0) { /* subnormal (or zero) */
        if (-e2 + 1 >= 64) {
            *bits = 0;
            return 0;
        }
        mant >>= -e2 + 1;
        mant += mant & 1;
        mant >>= 1;
        *bits = mant; /* 2^52 here is the smallest normal, as it should be */
        return 0;
    }
    if (lo <= 1 && q >= -4 && q <= 23 && (mant & 3) == 1 && (mant << (upper + 9)) == hi)
        mant &= ~UINT64_C(1); /* exactly halfway: to even */
    mant += mant & 1;
    mant >>= 1;
    if (mant >= (UINT64_C(2) << 52)) {
        mant = UINT64_C(1) << 52;
        e2++;
    }
    mant &= ~(UINT64_C(1) << 52);
    if (e2 >= 0x7ff) {
        *bits = INF_BITS;
        return 0;
    }
    *bits = mant | ((uint64_t)e2 << 52);
    return 0;
}

/* strtod on a bounded copy of the significant digits of [b, e) (digits and
 * at most one '.'), with value = digits * 10^exp10. */
static double fallback(const char *b, const char *e, int64_t exp10)
{
    char buf[FALLBACK_DIGITS + 40];
    size_t n = 0;
    int sticky = 0;
    int64_t cut = 0;
    for (const char *p = b; p < e; p++) {
        if (*p == '.')
            continue;
        if (n == 0 && *p == '0')
            continue;
        if (n < FALLBACK_DIGITS)
            buf[n++] = *p;
        else {
            sticky |= *p != '0';
            cut++;
        }
    }
    exp10 += cut;
    if (sticky) {
        buf[n++] = '1';
        exp10--;
    }
    if (exp10 > 99999)
        exp10 = 99999;
    if (exp10 < -99999)
        exp10 = -99999;
    snprintf(buf + n, sizeof buf - n, "e%ld", (long)exp10);
    return strtod(buf, NULL);
}

/* An exponent "<letter>[+-]digits" at p (letter in either case): its value
 * (clamped to +-10^9) in *ev and the end; p and 0 when there is none. */
static const char *parse_exponent(const char *p, const char *end, char letter, int64_t *ev)
{
    *ev = 0;
    if (p >= end || (*p | 0x20) != letter)
        return p;
    const char *q = p + 1;
    int neg = 0;
    if (q < end && (*q == '+' || *q == '-')) {
        neg = *q == '-';
        q++;
    }
    if (q >= end || !is_digit(*q))
        return p;
    int64_t v = 0;
    while (q < end && is_digit(*q)) {
        if (v < 1000000000)
            v = v * 10 + (*q - '0');
        q++;
    }
    *ev = neg ? -v : v;
    return q;
}

static int hex_value(char ch)
{
    if (ch >= '0' && ch <= '9')
        return ch - '0';
    ch = (char)(ch | 0x20);
    return ch >= 'a' && ch <= 'f' ? ch - 'a' + 10 : -1;
}

/* C99 hexadecimal significand after "0x" at p, with an optional binary
 * exponent "p[+-]digits": the value, correctly rounded (ties to even), in
 * *v. Returns the end, or NULL when no hexadecimal digit follows. */
static const char *parse_hex(const char *p, const char *end, double *v)
{
    uint64_t m = 0;
    int64_t be = 0;
    int n = 0, any = 0, sticky = 0;
    for (int frac = 0;; p++) {
        if (p < end && *p == '.' && !frac) {
            frac = 1;
            continue;
        }
        int d = p < end ? hex_value(*p) : -1;
        if (d < 0)
            break;
        any = 1;
        if (n < 16) {
            if (n || d) {
                m = m << 4 | (uint64_t)d;
                n++;
            }
            be -= frac ? 4 : 0;
        } else {
            sticky |= d != 0;
            be += frac ? 0 : 4;
        }
    }
    if (!any)
        return NULL;
    int64_t ev = 0;
    p = parse_exponent(p, end, 'p', &ev);
    be += ev;
    if (m == 0) {
        *v = 0.0;
        return p;
    }
    const int lz = clz64(m);
    m <<= lz;
    be -= lz;
    int64_t e = be + 63; /* m * 2^be lies in [2^e, 2^(e+1)) */
    if (e > 1023) {
        *v = INFINITY;
        return p;
    }
    int64_t shift = e >= -1022 ? 11 : 11 + (-1022 - e);
    if (shift > 64) {
        *v = 0.0;
        return p;
    }
    prs_u128 wide = (prs_u128)m << 1 | (prs_u128)(sticky != 0); /* one extra sticky bit */
    uint64_t kept = (uint64_t)(wide >> (shift + 1));
    prs_u128 rem = wide & ((((prs_u128)1) << (shift + 1)) - 1);
    prs_u128 half = ((prs_u128)1) << shift;
    if (rem > half || (rem == half && (kept & 1)))
        kept++;
    uint64_t bits;
    if (e >= -1022) {
        if (kept == UINT64_C(1) << 53) {
            kept >>= 1;
            e++;
        }
        if (e > 1023) {
            *v = INFINITY;
            return p;
        }
        bits = ((uint64_t)(e + 1023) << 52) | (kept & ((UINT64_C(1) << 52) - 1));
    } else {
        bits = kept; /* 2^52 after rounding is the smallest normal */
    }
    *v = from_bits(bits);
    return p;
}

static int lower_eq(const char *p, const char *end, const char *word)
{
    for (; *word; word++, p++)
        if (p >= end || (*p | 0x20) != *word)
            return 0;
    return 1;
}

geom_status geom_parse_double(const char *s, const char *end, double *out, const char **stop)
{
    if (stop)
        *stop = s;
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    *out = 0.0;
    if (!s || !end || end < s)
        return GEOM_ERR_INVALID_ARG;
    const char *p = s;
    int neg = 0;
    if (p < end && (*p == '+' || *p == '-')) {
        neg = *p == '-';
        p++;
    }
    if (p < end && ((*p | 0x20) == 'i' || (*p | 0x20) == 'n')) {
        double v;
        if (lower_eq(p, end, "infinity")) {
            p += 8;
            v = INFINITY;
        } else if (lower_eq(p, end, "inf")) {
            p += 3;
            v = INFINITY;
        } else if (lower_eq(p, end, "nan")) {
            p += 3;
            v = NAN;
        } else {
            return GEOM_ERR_PARSE;
        }
        *out = neg ? -v : v;
        if (stop)
            *stop = p;
        return GEOM_OK;
    }

    if (end - p >= 2 && p[0] == '0' && (p[1] | 0x20) == 'x') {
        double v;
        const char *q = parse_hex(p + 2, end, &v);
        if (q) {
            *out = neg ? -v : v;
            if (stop)
                *stop = q;
            return isinf(v) ? GEOM_ERR_DOMAIN : GEOM_OK;
        }
    }

    /* significand: the first 19 significant digits in w; value is
     * (all significant digits) * 10^(dexp + exponent). One pass over the
     * integer and the fraction digits, which accumulate alike; dexp counts
     * the digits after the point. */
    const char *mstart = p, *dot = NULL;
    uint64_t w = 0;
    int64_t nd = 0;
    int cut_nonzero = 0;
    for (; p < end; p++) {
        unsigned d = (unsigned)(*p - '0');
        if (d > 9) {
            if (*p == '.' && !dot) {
                dot = p;
                continue;
            }
            break;
        }
        if (nd < 19) {
            if (nd || d) {
                w = w * 10 + d;
                nd++;
            }
        } else {
            nd++;
            cut_nonzero |= d != 0;
        }
    }
    int64_t dexp = dot ? -(int64_t)(p - dot - 1) : 0;
    int any = p - mstart > (dot != NULL); /* a digit, not only a point */
    if (!any && dot)
        p = dot;
    if (!any)
        return GEOM_ERR_PARSE;
    const char *mend = p;
    int64_t ev = 0;
    p = parse_exponent(p, end, 'e', &ev);
    if (stop)
        *stop = p;

    double v;
    if (w == 0) {
        v = 0.0;
    } else {
        int64_t extra = nd > 19 ? nd - 19 : 0; /* digits cut from w */
        int64_t q = dexp + ev + extra;
        uint64_t bits, bits1;
        if (!extra && w <= (UINT64_C(1) << 53) && q >= -22 && q <= 22) {
            v = (double)w;
            v = q < 0 ? v / exact_pow10[-q] : v * exact_pow10[q];
        } else if (q + 19 < GEOM__POW5_QMIN) {
            v = 0.0; /* below 10^-324 */
        } else if (q > 310) {
            v = INFINITY;
        } else if (eisel_lemire(w, q, &bits) == 0 &&
                   (!extra || !cut_nonzero ||
                    (eisel_lemire(w + 1, q, &bits1) == 0 && bits1 == bits))) {
            v = from_bits(bits);
        } else {
            v = fallback(mstart, mend, dexp + ev);
        }
    }
    *out = neg ? -v : v;
    return isinf(v) ? GEOM_ERR_DOMAIN : GEOM_OK;
}
