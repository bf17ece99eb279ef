/*
 * Numbers: core's geom_format_double (Ryu, shortest round-trip) against
 * printf "%.17g" and the printer it replaced (the first of %.15g, %.16g,
 * %.17g that reads back, via strtod), and geom_parse_double (Eisel-Lemire)
 * against glibc's strtod (on NUL-terminated copies), over the same random
 * doubles (uniform bit patterns of finite values, and values in [-10, 10]
 * as mesh files hold). Prints ns per value, the ratio, the mean output
 * length and the errors (values that do not read back / differ from
 * strtod: both must be 0).
 * Usage: bench_numbers [N]   (default 1000000)
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "geom/core.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts); /* CPU time: the machine is shared */
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static unsigned long long rng = 88172645463325252ull;
static unsigned long long rnd(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

static size_t old_format(double x, char *buf)
{
    int n = 0;
    for (int p = 15; p <= 17; p++) {
        n = snprintf(buf, 32, "%.*g", p, x);
        if (p == 17 || strtod(buf, NULL) == x)
            break;
    }
    return (size_t)n;
}

/* Keeps the timed results alive (file scope: no unused-variable warning). */
static volatile size_t sink;

static void run(const char *label, const double *x, size_t n)
{
    char *text = malloc(n * 32);
    size_t *len = malloc(n * sizeof *len);
    char buf[32];
    memset(text, 0, n * 32); /* page faults out of the timed loops */
    memset(len, 0, n * sizeof *len);
    double t0 = now();
    size_t total = 0;
    for (size_t i = 0; i < n; i++) /* into one buffer, as snprintf below */
        total += geom_format_double(x[i], buf);
    double t_ryu = now() - t0;
    sink += buf[0];
    for (size_t i = 0; i < n; i++)
        len[i] = geom_format_double(x[i], text + 32 * i);
    t0 = now();
    size_t total17 = 0;
    for (size_t i = 0; i < n; i++)
        total17 += (size_t)snprintf(buf, sizeof buf, "%.17g", x[i]);
    double t_17g = now() - t0;
    t0 = now();
    size_t total_old = 0;
    for (size_t i = 0; i < n; i++)
        total_old += old_format(x[i], buf);
    double t_old = now() - t0;

    /* parse the shortest texts, and 17-digit texts */
    char *t17 = malloc(n * 32);
    size_t *l17 = malloc(n * sizeof *l17);
    for (size_t i = 0; i < n; i++)
        l17[i] = (size_t)snprintf(t17 + 32 * i, 32, "%.17g", x[i]);
    for (int style = 0; style < 2; style++) {
        const char *tx = style ? t17 : text;
        const size_t *lx = style ? l17 : len;
        size_t bad = 0, bad_strtod = 0;
        double v;
        t0 = now();
        for (size_t i = 0; i < n; i++) {
            const char *s = tx + 32 * i;
            geom_parse_double(s, s + lx[i], &v, NULL);
            bad += v != x[i];
        }
        double t_el = now() - t0;
        t0 = now();
        for (size_t i = 0; i < n; i++) {
            /* strtod needs a NUL-terminated copy when reading from a buffer */
            memcpy(buf, tx + 32 * i, lx[i]);
            buf[lx[i]] = '\0';
            v = strtod(buf, NULL);
            bad_strtod += v != x[i];
        }
        double t_strtod = now() - t0;
        printf("%-14s parse %-9s geom_parse_double %6.1f ns  strtod %6.1f ns  ratio %.2f  "
               "errors %zu / %zu\n",
               label, style ? "%.17g" : "shortest", 1e9 * t_el / (double)n,
               1e9 * t_strtod / (double)n, t_el / t_strtod, bad, bad_strtod);
    }
    printf("%-14s print geom_format_double %6.1f ns (mean %.2f chars)  %%.17g %6.1f ns (%.2f "
           "chars)  old 15/16/17 %6.1f ns (%.2f chars)  ratio vs %%.17g %.2f, vs old %.2f\n",
           label, 1e9 * t_ryu / (double)n, (double)total / (double)n, 1e9 * t_17g / (double)n,
           (double)total17 / (double)n, 1e9 * t_old / (double)n,
           (double)total_old / (double)n, t_ryu / t_17g, t_ryu / t_old);
    sink += total;
    free(text);
    free(len);
    free(t17);
    free(l17);
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? (size_t)strtoull(argv[1], NULL, 10) : 1000000;
    double *x = malloc(n * sizeof *x);
    for (size_t i = 0; i < n;) {
        unsigned long long b = rnd();
        double v;
        memcpy(&v, &b, sizeof v);
        if (isfinite(v))
            x[i++] = v;
    }
    run("random bits", x, n);
    for (size_t i = 0; i < n; i++)
        x[i] = 20.0 * ((double)(rnd() >> 11) * 0x1p-53) - 10.0;
    run("[-10, 10]", x, n);
    free(x);
    return 0;
}
