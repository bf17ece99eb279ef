/*
 * Shortest round-trip formatting of doubles: Ryu (Ulf Adams, "Ryu: Fast
 * Float-to-String Conversion", PLDI 2018).
 *
 * A finite nonzero double is m2 * 2^e2. The numbers that read back as it
 * form the interval between the midpoints to its neighbours; Ryu scales the
 * interval's ends and centre (4*m2 - 1 - shift, 4*m2, 4*m2 + 2, times
 * 2^(e2-2)) by a power of ten with one 64x128-bit multiplication each
 * (floor(m * 2^e / 10^q) from a 128-bit significand of 5^q or 5^-q), chosen
 * so that the results have about 17 digits, then removes decimal digits
 * while the ends still differ. The digits left are the shortest that lie in
 * the interval, and among those the closest to the exact value (ties to
 * even). Exactness where the scaled ends have trailing zeros (the interval
 * ends are included when m2 is even, and a removed "5" may be an exact
 * tie) is tracked with divisibility by powers of 5 and 2, as in the paper.
 */
#include "core/internal.h"
#include "core/numbers_internal.h"

#include <stdio.h>
#include <string.h>

__extension__ typedef unsigned __int128 fmt_u128;

/* floor(log10(2^e)) for 0 <= e <= 1650 */
static uint32_t log10_pow2(int32_t e) { return ((uint32_t)e * 78913u) >> 18; }
/* floor(log10(5^e)) for 0 <= e <= 2620 */
static uint32_t log10_pow5(int32_t e) { return ((uint32_t)e * 732923u) >> 20; }

static uint32_t pow5_factor(uint64_t v)
{
    uint32_t n = 0;
    while (v != 0 && v % 5 == 0) {
        v /= 5;
        n++;
    }
    return n;
}

static int divisible_pow5(uint64_t v, uint32_t p) { return pow5_factor(v) >= p; }
static int divisible_pow2(uint64_t v, uint32_t p) { return p < 64 && (v & ((UINT64_C(1) << p) - 1)) == 0; }

/* floor(m * mul / 2^shift) for a 128-bit mul, 64 <= shift < 192; m < 2^56. */
static uint64_t mul_shift(uint64_t m, const uint64_t mul[2], int32_t shift)
{
    fmt_u128 lo = (fmt_u128)m * mul[1];
    fmt_u128 hi = (fmt_u128)m * mul[0];
    fmt_u128 sum = hi + (lo >> 64);
    return (uint64_t)(sum >> (shift - 64));
}

typedef struct dec {
    uint64_t digits; /* the significand, no trailing zeros required */
    int32_t exp;     /* value = digits * 10^exp */
} dec;

/* Shortest decimal for the finite, nonzero |x| with raw fields (mant, bexp). */
static dec ryu(uint64_t mant, uint32_t bexp)
{
    int32_t e2;
    uint64_t m2;
    if (bexp == 0) {
        e2 = 1 - 1023 - 52 - 2;
        m2 = mant;
    } else {
        e2 = (int32_t)bexp - 1023 - 52 - 2;
        m2 = mant | (UINT64_C(1) << 52);
    }
    const int accept_ends = (m2 & 1) == 0;

    /* the interval in units of 2^e2: [mv - 1 - mm_shift, mv + 2] around mv;
     * the lower gap is half as wide at a power of two */
    const uint64_t mv = 4 * m2;
    const uint32_t mm_shift = mant != 0 || bexp <= 1;

    uint64_t vr, vp, vm;
    int32_t e10;
    int vm_zeros = 0, vr_zeros = 0;
    if (e2 >= 0) {
        /* multiply by 2^e2 / 10^q with 5^-q rounded up (127 bits) */
        const uint32_t q = log10_pow2(e2) - (e2 > 3);
        e10 = (int32_t)q;
        const uint64_t *t = geom__pow5_128[-(int32_t)q - GEOM__POW5_QMIN];
        /* the table holds 2^(bits + 127) / 5^q for q > 0 (2^127 for q = 0):
         * halve it to 127 bits, then round up */
        uint64_t inv[2];
        inv[0] = q ? t[0] >> 1 : t[0];
        inv[1] = q ? (t[1] >> 1) | (t[0] << 63) : t[1];
        inv[1] += 1;
        inv[0] += inv[1] == 0;
        const int32_t k = 127 + geom__pow5_bits((int32_t)q) - 1;
        const int32_t sh = -e2 + (int32_t)q + k;
        vr = mul_shift(mv, inv, sh);
        vp = mul_shift(mv + 2, inv, sh);
        vm = mul_shift(mv - 1 - mm_shift, inv, sh);
        if (q <= 21) {
            /* only here can the scaled values be exact integers */
            if (mv % 5 == 0)
                vr_zeros = divisible_pow5(mv, q);
            else if (accept_ends)
                vm_zeros = divisible_pow5(mv - 1 - mm_shift, q);
            else
                vp -= (uint64_t)divisible_pow5(mv + 2, q);
        }
    } else {
        /* multiply by 2^e2 / 10^(q + e2) = 5^i / 2^q with i = -e2 - q */
        const uint32_t q = log10_pow5(-e2) - (-e2 > 1);
        e10 = (int32_t)q + e2;
        const int32_t i = -e2 - (int32_t)q;
        const uint64_t *t = geom__pow5_128[i - GEOM__POW5_QMIN];
        const int32_t k = geom__pow5_bits(i) - 128;
        const int32_t sh = (int32_t)q - k;
        vr = mul_shift(mv, t, sh);
        vp = mul_shift(mv + 2, t, sh);
        vm = mul_shift(mv - 1 - mm_shift, t, sh);
        if (q <= 1) {
            /* mv * 5^i / 2^q is an integer: its trailing zeros are exact */
            vr_zeros = 1;
            if (accept_ends)
                vm_zeros = mm_shift == 1;
            else
                vp--;
        } else if (q < 63) {
            vr_zeros = divisible_pow2(mv, q);
        }
    }

    /* remove digits while the interval's ends differ in what is left */
    int32_t removed = 0;
    uint8_t last = 0;
    uint64_t out;
    if (vm_zeros || vr_zeros) {
        while (vp / 10 > vm / 10) {
            vm_zeros &= vm % 10 == 0;
            vr_zeros &= last == 0;
            last = (uint8_t)(vr % 10);
            vr /= 10;
            vp /= 10;
            vm /= 10;
            removed++;
        }
        if (vm_zeros) {
            while (vm % 10 == 0) {
                vr_zeros &= last == 0;
                last = (uint8_t)(vr % 10);
                vr /= 10;
                vp /= 10;
                vm /= 10;
                removed++;
            }
        }
        if (vr_zeros && last == 5 && vr % 2 == 0)
            last = 4; /* an exact tie: round to even */
        out = vr + ((vr == vm && (!accept_ends || !vm_zeros)) || last >= 5);
    } else {
        int round_up = 0;
        if (vp / 100 > vm / 100) {
            round_up = vr % 100 >= 50;
            vr /= 100;
            vp /= 100;
            vm /= 100;
            removed += 2;
        }
        while (vp / 10 > vm / 10) {
            round_up = vr % 10 >= 5;
            vr /= 10;
            vp /= 10;
            vm /= 10;
            removed++;
        }
        out = vr + (vr == vm || round_up);
    }
    dec d = {out, e10 + removed};
    return d;
}

static const uint64_t pow10_u64[20] = {
    UINT64_C(1), UINT64_C(10), UINT64_C(100), UINT64_C(1000), UINT64_C(10000),
    UINT64_C(100000), UINT64_C(1000000), UINT64_C(10000000), UINT64_C(100000000),
    UINT64_C(1000000000), UINT64_C(10000000000), UINT64_C(100000000000),
    UINT64_C(1000000000000), UINT64_C(10000000000000), UINT64_C(100000000000000),
    UINT64_C(1000000000000000), UINT64_C(10000000000000000), UINT64_C(100000000000000000),
    UINT64_C(1000000000000000000), UINT64_C(10000000000000000000)};

int geom__decimal_length(uint64_t v)
{
    /* 1233 / 4096 ~ log10(2): t + 1 is the length or one more (v | 1:
     * 0 has one digit, and v | 1 < 10^t exactly when v < 10^t) */
    const uint64_t w = v | 1;
    const int t = ((64 - __builtin_clzll(w)) * 1233) >> 12;
    return t - (w < pow10_u64[t]) + 1;
}

/* "00" .. "99" */
static const char digit_pairs[201] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

/* Exactly n (<= 10) digits of w, ending at e. */
static void put_digits32(char *e, uint32_t w, int n)
{
    while (n >= 2) {
        uint32_t q = w / 100;
        e -= 2;
        memcpy(e, digit_pairs + 2 * (w - 100 * q), 2);
        w = q;
        n -= 2;
    }
    if (n)
        e[-1] = (char)('0' + w);
}

void geom__put_digits(char *p, uint64_t v, int n)
{
    char *e = p + n;
    /* eight digits a step in 32 bits */
    while (n > 8) {
        uint64_t q = v / 100000000;
        put_digits32(e, (uint32_t)(v - 100000000 * q), 8);
        e -= 8;
        n -= 8;
        v = q;
    }
    put_digits32(e, (uint32_t)v, n);
}

/* The n digits of v at p, with a '.' after the first `point` digits when
 * 0 < point < n; returns the end. The digits after the point and those
 * before it are written separately, in place, two at a time (no staging
 * buffer: reading back bytes just stored one at a time stalls). */
static char *emit_digits(char *p, uint64_t v, int n, int point)
{
    if (point <= 0 || point >= n) {
        geom__put_digits(p, v, n);
        return p + n;
    }
    const uint64_t scale = pow10_u64[n - point];
    const uint64_t hi = v / scale;
    geom__put_digits(p, hi, point);
    p[point] = '.';
    geom__put_digits(p + point + 1, v - hi * scale, n - point);
    return p + n + 1;
}

size_t geom_format_double(double x, char buf[GEOM_DOUBLE_CHARS])
{
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    const int neg = (int)(bits >> 63);
    const uint64_t mant = bits & ((UINT64_C(1) << 52) - 1);
    const uint32_t bexp = (uint32_t)(bits >> 52) & 0x7ff;
    char *p = buf;
    if (bexp == 0x7ff) {
        if (mant) {
            memcpy(buf, "nan", 4);
            return 3;
        }
        if (neg)
            *p++ = '-';
        memcpy(p, "inf", 4);
        return (size_t)(p - buf) + 3;
    }
    if (neg)
        *p++ = '-';
    if (bexp == 0 && mant == 0) {
        *p++ = '0';
        *p = '\0';
        return (size_t)(p - buf);
    }
    dec d = ryu(mant, bexp);
    /* drop trailing zeros (Ryu may leave some) */
    while (d.digits % 10 == 0) {
        d.digits /= 10;
        d.exp++;
    }
    const int n = geom__decimal_length(d.digits);
    const int X = d.exp + n - 1; /* exponent of the first digit */
    const int P = n > 15 ? n : 15;
    if (X >= -4 && X < P) {
        /* fixed notation, as printf's %.<P>g without trailing zeros */
        if (X < 0) {
            *p++ = '0';
            *p++ = '.';
            for (int i = -1; i > X; i--)
                *p++ = '0';
            p = emit_digits(p, d.digits, n, 0);
        } else if (X + 1 >= n) {
            p = emit_digits(p, d.digits, n, 0);
            for (int i = n; i <= X; i++)
                *p++ = '0';
        } else {
            p = emit_digits(p, d.digits, n, X + 1);
        }
    } else {
        p = emit_digits(p, d.digits, n, 1);
        *p++ = 'e';
        int e = X;
        if (e < 0) {
            *p++ = '-';
            e = -e;
        } else {
            *p++ = '+';
        }
        if (e >= 100) {
            *p++ = (char)('0' + e / 100);
            e %= 100;
        }
        *p++ = (char)('0' + e / 10);
        *p++ = (char)('0' + e % 10);
    }
    *p = '\0';
    return (size_t)(p - buf);
}

size_t geom_format_double_digits(double x, int digits, char buf[GEOM_DOUBLE_CHARS])
{
    if (digits <= 0)
        return geom_format_double(x, buf);
    if (!isfinite(x))
        return geom_format_double(x, buf);
    if (digits > 17)
        digits = 17;
    char tmp[48];
    int n = snprintf(tmp, sizeof tmp, "%.*g", digits, x);
    /* whatever the locale's decimal point, write '.' */
    size_t j = 0;
    for (int i = 0; i < n && j + 1 < GEOM_DOUBLE_CHARS; i++) {
        char ch = tmp[i];
        if ((ch >= '0' && ch <= '9') || ch == '-' || ch == '+' || ch == 'e')
            buf[j++] = ch;
        else if (j == 0 || buf[j - 1] != '.')
            buf[j++] = '.';
    }
    buf[j] = '\0';
    return j;
}
