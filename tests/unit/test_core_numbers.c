/*
 * geom_format_double (Ryu) and geom_parse_double (Eisel-Lemire) against the
 * C library: glibc's strtod is correctly rounded and its printf prints exact
 * decimal expansions, so both are independent references.
 *  - printer: over millions of random bit patterns (all exponents,
 *    subnormals) and special values, the output reads back bit for bit
 *    through strtod, no shorter correctly rounded decimal (%.{n-1}e) reads
 *    back, and when the correctly rounded n-digit decimal reads back the
 *    printer chose exactly those digits;
 *  - parser: equal to strtod, bit for bit, on random doubles printed with 1
 *    to 19 digits, random 17-19 digit mantissas with any exponent, exact
 *    midpoints between neighbouring doubles (hundreds of digits) and their
 *    neighbours one unit away in the 30th or 800th digit, powers of 10 and
 *    2, and the overflow and underflow edges.
 * GEOM_NUMBERS_TEST_SCALE (environment) multiplies the random counts.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/core.h"

static uint64_t rng_state = 0x853c49e6748fea9bull;
static uint64_t rnd(void)
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static size_t scaled(size_t n)
{
    const char *s = getenv("GEOM_NUMBERS_TEST_SCALE");
    double f = s ? atof(s) : 1.0;
    if (!(f > 0))
        f = 1.0;
    return (size_t)((double)n * f) + 1;
}

static double bits_to_double(uint64_t b)
{
    double x;
    memcpy(&x, &b, sizeof x);
    return x;
}

static uint64_t double_bits(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

static int same_bits(double a, double b) { return double_bits(a) == double_bits(b); }

/* significant digits of a printed number (no sign, point or exponent) */
static int sig_digits(const char *s, char *dig)
{
    int n = 0, started = 0;
    for (; *s && *s != 'e'; s++) {
        if (*s >= '0' && *s <= '9') {
            if (*s != '0')
                started = 1;
            if (started)
                dig[n++] = *s;
        }
    }
    while (n > 1 && dig[n - 1] == '0')
        n--;
    if (n == 0)
        dig[n++] = '0';
    dig[n] = '\0';
    return n;
}

static unsigned long printer_failures;

static void check_print(double x)
{
    char buf[GEOM_DOUBLE_CHARS], ref[64], d1[32], d2[32];
    size_t len = geom_format_double(x, buf);
    if (len != strlen(buf) || len > 24) {
        printer_failures++;
        return;
    }
    char *end;
    double y = strtod(buf, &end);
    if (*end || !same_bits(x, y)) {
        if (printer_failures++ < 10)
            fprintf(stderr, "printer: %a -> '%s' reads back as %a\n", x, buf, y);
        return;
    }
    double z;
    const char *stop;
    if (geom_parse_double(buf, buf + len, &z, &stop) != GEOM_OK || stop != buf + len ||
        !same_bits(x, z)) {
        if (printer_failures++ < 10)
            fprintf(stderr, "printer/parser: %a -> '%s' parses as %a\n", x, buf, z);
        return;
    }
    /* never longer than the printer it replaced: the first of %.15g,
     * %.16g, %.17g that reads back */
    for (int p = 15; p <= 17; p++) {
        int k = snprintf(ref, sizeof ref, "%.*g", p, x);
        if (p == 17 || same_bits(strtod(ref, NULL), x)) {
            if ((int)len > k && printer_failures++ < 10)
                fprintf(stderr, "printer: %a -> '%s', longer than '%s'\n", x, buf, ref);
            break;
        }
    }
    if (x == 0)
        return;
    int n = sig_digits(buf, d1);
    if (n > 1) {
        /* the correctly rounded (n-1)-digit decimal must not read back */
        snprintf(ref, sizeof ref, "%.*e", n - 2, x);
        if (same_bits(strtod(ref, NULL), x)) {
            if (printer_failures++ < 10)
                fprintf(stderr, "printer: %a -> '%s' but '%s' is shorter\n", x, buf, ref);
            return;
        }
    }
    /* if the correctly rounded n-digit decimal reads back, it is the one */
    snprintf(ref, sizeof ref, "%.*e", n - 1, x);
    if (same_bits(strtod(ref, NULL), x)) {
        sig_digits(ref, d2);
        if (strcmp(d1, d2) != 0 && printer_failures++ < 10)
            fprintf(stderr, "printer: %a -> '%s', closest is '%s'\n", x, buf, ref);
    }
}

static void test_print_special(void **state)
{
    (void)state;
    char buf[GEOM_DOUBLE_CHARS];
    struct {
        double x;
        const char *s;
    } cases[] = {
        {0.0, "0"},
        {-0.0, "-0"},
        {1.0, "1"},
        {-2.5, "-2.5"},
        {0.1, "0.1"},
        {1.0 / 3.0, "0.3333333333333333"},
        {100000.0, "100000"},
        {1e15, "1e+15"},
        {123456789012345.0, "123456789012345"},
        {1e-4, "0.0001"},
        {1e-5, "1e-05"},
        {1.5e-7, "1.5e-07"},
        {1e20, "1e+20"},
        {1e100, "1e+100"},
        {DBL_MAX, "1.7976931348623157e+308"},
        {DBL_MIN, "2.2250738585072014e-308"},
        {-DBL_MIN, "-2.2250738585072014e-308"},
        {DBL_TRUE_MIN, "5e-324"},
        {9007199254740993.0, "9007199254740992"},
        {0.30000000000000004, "0.30000000000000004"},
        {5e-324 * 3, "1.5e-323"},
        {INFINITY, "inf"},
        {-INFINITY, "-inf"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        size_t n = geom_format_double(cases[i].x, buf);
        if (strcmp(buf, cases[i].s) != 0)
            fprintf(stderr, "%a: '%s', expected '%s'\n", cases[i].x, buf, cases[i].s);
        assert_string_equal(buf, cases[i].s);
        assert_int_equal(n, strlen(cases[i].s));
    }
    geom_format_double(NAN, buf);
    assert_string_equal(buf, "nan");
    geom_format_double(-NAN, buf);
    assert_string_equal(buf, "nan");

    /* the %g-compatible notation choice, against printf over P = max(n, 15) */
    double xs[] = {1234.5, 0.000123, 1e16, 12345678901234567.0, 1.2345678901234567e16,
                   98765.4321e10, 3e-300, 7.0e22};
    for (size_t i = 0; i < sizeof xs / sizeof xs[0]; i++) {
        char ref[64], d[32];
        geom_format_double(xs[i], buf);
        int n = sig_digits(buf, d);
        snprintf(ref, sizeof ref, "%.*g", n > 15 ? n : 15, xs[i]);
        assert_string_equal(buf, ref);
    }

    /* fixed digits: printf's %.17g, '.' whatever the locale */
    assert_int_equal(geom_format_double_digits(0.1, 17, buf), 19);
    assert_string_equal(buf, "0.10000000000000001");
    geom_format_double_digits(2.0 / 3.0, 3, buf);
    assert_string_equal(buf, "0.667");
    geom_format_double_digits(1e300, 40, buf);
    assert_string_equal(buf, "1.0000000000000001e+300");
    geom_format_double_digits(0.1, 0, buf);
    assert_string_equal(buf, "0.1");
    geom_format_double_digits(-INFINITY, 17, buf);
    assert_string_equal(buf, "-inf");
}

static void test_print_random_bits(void **state)
{
    (void)state;
    printer_failures = 0;
    size_t n = scaled(1000000);
    for (size_t i = 0; i < n; i++) {
        double x = bits_to_double(rnd());
        if (isfinite(x))
            check_print(x);
    }
    /* subnormals, and values near the normal range's ends */
    for (size_t i = 0; i < scaled(200000); i++) {
        uint64_t b = rnd();
        check_print(bits_to_double(b & 0x800fffffffffffffull));              /* subnormal */
        check_print(bits_to_double((b & 0x800fffffffffffffull) | (1ull << 52))); /* e = 1 */
        check_print(bits_to_double((b & 0x800fffffffffffffull) | (0x7feull << 52)));
    }
    /* powers of two and ten, their neighbours, small integers */
    for (int e = -1074; e <= 1023; e++) {
        double x = ldexp(1.0, e);
        check_print(x);
        check_print(nextafter(x, 0));
        check_print(nextafter(x, INFINITY));
    }
    for (int e = -325; e <= 308; e++) {
        char s[32];
        snprintf(s, sizeof s, "1e%d", e);
        double x = strtod(s, NULL);
        check_print(x);
        check_print(nextafter(x, 0));
        check_print(nextafter(x, INFINITY));
    }
    for (int i = 0; i < 100000; i++)
        check_print((double)i);
    check_print(DBL_MAX);
    check_print(DBL_MIN);
    check_print(DBL_TRUE_MIN);
    check_print(-DBL_MAX);
    assert_int_equal(printer_failures, 0);
}

/* ---------------------------------------------------------------- parser */

static unsigned long parser_failures;

static void check_parse(const char *s)
{
    size_t len = strlen(s);
    char *end;
    double ref = strtod(s, &end);
    double got = 12345.0;
    const char *stop = NULL;
    geom_status st = geom_parse_double(s, s + len, &got, &stop);
    geom_status want = isinf(ref) ? GEOM_ERR_DOMAIN : GEOM_OK;
    if (st != want || stop != end || !same_bits(got, ref)) {
        if (parser_failures++ < 10)
            fprintf(stderr, "parser: '%.80s%s' (%zu chars): %a status %d, strtod %a\n", s,
                    len > 80 ? "..." : "", len, got, (int)st, ref);
    }
}

static void test_parse_syntax(void **state)
{
    (void)state;
    struct {
        const char *s;
        geom_status st;
        size_t used;
        double v;
    } cases[] = {
        {"0", GEOM_OK, 1, 0.0},
        {"-0", GEOM_OK, 2, -0.0},
        {"+1.5", GEOM_OK, 4, 1.5},
        {".5", GEOM_OK, 2, 0.5},
        {"5.", GEOM_OK, 2, 5.0},
        {"-.5e1", GEOM_OK, 5, -5.0},
        {"1e", GEOM_OK, 1, 1.0},
        {"1e+", GEOM_OK, 1, 1.0},
        {"1E-2x", GEOM_OK, 4, 0.01},
        {"2.5 3", GEOM_OK, 3, 2.5},
        {"1,5", GEOM_OK, 1, 1.0},
        {"inf", GEOM_OK, 3, INFINITY},
        {"-Infinity", GEOM_OK, 9, -INFINITY},
        {"INFINITE", GEOM_OK, 3, INFINITY},
        {"1e400", GEOM_ERR_DOMAIN, 5, INFINITY},
        {"-1e400", GEOM_ERR_DOMAIN, 6, -INFINITY},
        {"1e-400", GEOM_OK, 6, 0.0},
        {"0e999999999999999999", GEOM_OK, 20, 0.0},
        {"", GEOM_ERR_PARSE, 0, 0.0},
        {"-", GEOM_ERR_PARSE, 0, 0.0},
        {".", GEOM_ERR_PARSE, 0, 0.0},
        {"+.e1", GEOM_ERR_PARSE, 0, 0.0},
        {"e5", GEOM_ERR_PARSE, 0, 0.0},
        {" 1", GEOM_ERR_PARSE, 0, 0.0},
        {"in", GEOM_ERR_PARSE, 0, 0.0},
        {"0x10", GEOM_OK, 4, 16.0},
        {"0x", GEOM_OK, 1, 0.0},
        {"-0x.8p1", GEOM_OK, 7, -1.0},
        {"0x1p", GEOM_OK, 3, 1.0},
        {"0x1p-1075", GEOM_OK, 9, 0.0},
        {"0x1.8p-1075", GEOM_OK, 11, 0x1p-1074},
        {"0x1p1024", GEOM_ERR_DOMAIN, 8, INFINITY},
        /* exact values from Python's float.fromhex */
        {"0x21DDcA20eb3F2Bp-1076", GEOM_OK, 22, 0x0.87772883acfcbp-1022},
        {"0x3p-1076", GEOM_OK, 9, 0x1p-1074},
        {"0x5p-1076", GEOM_OK, 9, 0x1p-1074},
        {"0x7p-1076", GEOM_OK, 9, 0x1p-1073},
        {"0x1.fffffffffffff8p-1023", GEOM_OK, 24, 0x1p-1022},
        {"0x1.fffffffffffff7ffp-1023", GEOM_OK, 26, 0x1p-1022},
        {"0x1.ffffffffffffefffp-1023", GEOM_OK, 26, 0x0.fffffffffffffp-1022},
        {"0x1.fffffffffffff8p1023", GEOM_ERR_DOMAIN, 23, INFINITY},
        {"0x1.fffffffffffff7fffffp1023", GEOM_OK, 28, DBL_MAX},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *s = cases[i].s;
        double v = 99.0;
        const char *stop = NULL;
        geom_status st = geom_parse_double(s, s + strlen(s), &v, &stop);
        if (st != cases[i].st || (size_t)(stop - s) != cases[i].used || !same_bits(v, cases[i].v))
            fprintf(stderr, "'%s': status %d used %zu value %a\n", s, (int)st,
                    (size_t)(stop - s), v);
        assert_int_equal(st, cases[i].st);
        assert_int_equal((size_t)(stop - s), cases[i].used);
        assert_true(same_bits(v, cases[i].v));
    }
    double v;
    static const char nan_text[] = "nan";
    assert_true(geom_parse_double(nan_text, nan_text + 3, &v, NULL) == GEOM_OK && isnan(v));
    /* the end bounds the input: no read past it */
    const char t[] = {'1', '2', '5', 'e', '2'};
    assert_int_equal(geom_parse_double(t, t + 3, &v, NULL), GEOM_OK);
    assert_true(v == 125.0);
    assert_int_equal(geom_parse_double(t, t + 4, &v, NULL), GEOM_OK);
    assert_true(v == 125.0);
    assert_int_equal(geom_parse_double(NULL, t, &v, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_parse_double(t, t, NULL, NULL), GEOM_ERR_INVALID_ARG);
}

static void test_parse_random(void **state)
{
    (void)state;
    parser_failures = 0;
    char s[64];
    size_t n = scaled(400000);
    for (size_t i = 0; i < n; i++) {
        double x = bits_to_double(rnd() & 0x7fffffffffffffffull);
        if (!isfinite(x))
            continue;
        int digits = 1 + (int)(rnd() % 19);
        snprintf(s, sizeof s, "%.*g", digits, x);
        check_parse(s);
        snprintf(s, sizeof s, "%.17g", x);
        check_parse(s);
    }
    /* 15 to 19 digit mantissas with any exponent, in and out of range */
    for (size_t i = 0; i < n; i++) {
        int digits = 15 + (int)(rnd() % 5);
        uint64_t m = rnd() % 10000000000000000000ull;
        int e = (int)(rnd() % 700) - 360;
        snprintf(s, sizeof s, "%0*llue%d", digits, (unsigned long long)m, e);
        check_parse(s);
        snprintf(s, sizeof s, "0.%0*llue%d", digits, (unsigned long long)m, e);
        check_parse(s);
    }
    /* short mantissas over the whole exponent range (Clinger's path and
     * its edges), integers */
    for (size_t i = 0; i < n; i++) {
        uint64_t m = rnd() >> (rnd() % 64);
        int e = (int)(rnd() % 60) - 30;
        snprintf(s, sizeof s, "%llue%d", (unsigned long long)m, e);
        check_parse(s);
    }
    /* hexadecimal floats: random significands of 1 to 20 digits and any
     * binary exponent, against strtod */
    for (size_t i = 0; i < n / 4; i++) {
        int digits = 1 + (int)(rnd() % 20);
        char *p = s;
        p += sprintf(p, "0x");
        for (int k = 0; k < digits; k++) {
            if (k == (int)(rnd() % 8))
                *p++ = '.';
            *p++ = "0123456789abcdefABCDEF"[rnd() % 22];
        }
        sprintf(p, "p%d", (int)(rnd() % 2300) - 1150);
        /* glibc 2.36 rounds some hexadecimal subnormals wrongly (e.g.
         * 0x21ddca20eb3f2bp-1076: remainder 3/4, it rounds down): those are
         * checked against exact values in test_parse_syntax instead */
        if (fabs(strtod(s, NULL)) >= DBL_MIN)
            check_parse(s);
    }
    assert_int_equal(parser_failures, 0);
}

/* Exact decimal expansion of a long double (glibc prints exactly). */
static void exact(char *buf, size_t size, long double x)
{
    snprintf(buf, size, "%.1100Le", x);
    /* drop trailing zeros of the significand */
    char *e = strchr(buf, 'e');
    char *p = e;
    while (p > buf && p[-1] == '0')
        p--;
    if (p[-1] == '.')
        p--;
    memmove(p, e, strlen(e) + 1);
}

/* Change the digit at significant position k (0-based) by +-1 without
 * carrying through: only where it is not 0 or 9. */
static int nudge(char *s, int k, int up)
{
    int seen = 0;
    for (char *p = s; *p && *p != 'e'; p++) {
        if (*p < '0' || *p > '9')
            continue;
        if (seen++ == k) {
            if ((up && *p == '9') || (!up && *p == '0'))
                return 0;
            *p = (char)(*p + (up ? 1 : -1));
            return 1;
        }
    }
    return 0;
}

static void test_parse_halfway(void **state)
{
    (void)state;
    parser_failures = 0;
    static char buf[1300], t[1300];
    size_t n = scaled(30000);
    for (size_t i = 0; i < n; i++) {
        double x;
        switch (i % 4) {
        case 0: x = bits_to_double(rnd() & 0x7fefffffffffffffull); break;
        case 1: x = bits_to_double(rnd() & 0x000fffffffffffffull); break; /* subnormal */
        case 2: x = ldexp((double)(rnd() >> 11), (int)(rnd() % 120) - 60); break;
        default: x = (double)(rnd() >> (11 + rnd() % 40)); break;
        }
        if (!isfinite(x) || !isfinite(nextafter(x, INFINITY)))
            continue;
        long double mid = ((long double)x + (long double)nextafter(x, INFINITY)) / 2;
        exact(buf, sizeof buf, mid);
        check_parse(buf);
        int len = (int)(strchr(buf, 'e') - buf);
        int k = (int)(rnd() % 3) == 0 ? 29 : len - 3;
        memcpy(t, buf, sizeof buf);
        if (nudge(t, k, 1))
            check_parse(t);
        memcpy(t, buf, sizeof buf);
        if (nudge(t, k, 0))
            check_parse(t);
        /* a long tail of zeros, then a 1: just above the midpoint */
        char *e = strchr(buf, 'e');
        char ex[16];
        snprintf(ex, sizeof ex, "%s", e);
        if (strchr(buf, '.')) {
            size_t at = (size_t)(e - buf);
            memset(buf + at, '0', 60);
            buf[at + 60] = '1';
            strcpy(buf + at + 61, ex);
            check_parse(buf);
        }
    }
    assert_int_equal(parser_failures, 0);
}

static void test_parse_edges(void **state)
{
    (void)state;
    parser_failures = 0;
    static char buf[1300];
    char s[64];
    for (int e = -400; e <= 400; e++) {
        snprintf(s, sizeof s, "1e%d", e);
        check_parse(s);
        snprintf(s, sizeof s, "9.999999999999999999e%d", e);
        check_parse(s);
        snprintf(s, sizeof s, "4.9406564584124654e%d", e);
        check_parse(s);
    }
    for (int e = -1074; e <= 1023; e++) {
        exact(buf, sizeof buf, ldexpl(1.0L, e));
        check_parse(buf);
        /* half-way below and above a power of two */
        exact(buf, sizeof buf, ldexpl(1.0L, e) * (1.0L - 0x1p-54L));
        check_parse(buf);
        exact(buf, sizeof buf, ldexpl(1.0L, e) * (1.0L + 0x1p-53L));
        check_parse(buf);
    }
    const char *fixed[] = {
        "1.7976931348623157e308", "1.7976931348623158e308", "1.7976931348623159e308",
        "179769313486231580793728971405303415079934132710037826936173778980444968292764750946649017977587207096330286416692887910946555547851940402630657488671505820681908902000708383676273854845817711531764475730270069855571366959622842914819860834936475292719074168444365510704342711559699508093042880177904174497791.9999999999999999999999999999999999999999999999999999999999999999999999",
        "2.2250738585072014e-308", "2.2250738585072011e-308", "2.2250738585072012e-308",
        "4.9406564584124654e-324", "2.4703282292062328e-324", "2.4703282292062327e-324",
        "2.4703282292062327208828439643411068618252990130716238221279284125033775363510437593264991818081799618989828234772285886546332835517796989819938739800539093906315035659515570226392290858392449105184435931802849936536152500319370457678249219365623669863658480757001585769269903706311928279558551332927834338409351978015531246597263579574622766465272827220056374006485499977096599470454020828166226237857393450736339007967761930577506740176324673600968951340535537458516661134223766678604162159680461914467291840300530057530849048765391711386591646239524912623653881879636239373280423891018672348497668235089863388587925628302755995657524455507255189313690836254779186948667994968324049705821028513185451396213837722826145437693412532098591327667236328125e-324",
        "2.4703282292062327208828439643411068618252990130716238221279284125033775363510437593264991818081799618989828234772285886546332835517796989819938739800539093906315035659515570226392290858392449105184435931802849936536152500319370457678249219365623669863658480757001585769269903706311928279558551332927834338409351978015531246597263579574622766465272827220056374006485499977096599470454020828166226237857393450736339007967761930577506740176324673600968951340535537458516661134223766678604162159680461914467291840300530057530849048765391711386591646239524912623653881879636239373280423891018672348497668235089863388587925628302755995657524455507255189313690836254779186948667994968324049705821028513185451396213837722826145437693412532098591327667236328125000000000000000001e-324",
        "0.000000000000000000000000000000000000000000000000000000000000000000000000000000001",
        "9007199254740993", "9007199254740993.0000000000000000000000001",
        "9007199254740992.9999999999999999999999999", "18446744073709551615",
        "18446744073709551616", "123456789012345678901234567890e-30", "7.2057594037927933e16",
        "1e23", "8.41e21", "2.2250738585072014E-308", "1.00000000000000011102230246251565404236316680908203125",
        "1.00000000000000011102230246251565404236316680908203124",
        "1.00000000000000011102230246251565404236316680908203126",
    };
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
        check_parse(fixed[i]);
    /* 1000 digits of zeros then a number */
    memset(buf, '0', 1000);
    strcpy(buf + 1000, "1.25e-3");
    check_parse(buf);
    buf[0] = '.';
    check_parse(buf);
    assert_int_equal(parser_failures, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_print_special),
        cmocka_unit_test(test_print_random_bits),
        cmocka_unit_test(test_parse_syntax),
        cmocka_unit_test(test_parse_random),
        cmocka_unit_test(test_parse_halfway),
        cmocka_unit_test(test_parse_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
