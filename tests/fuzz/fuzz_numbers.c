/*
 * libFuzzer target over the tools' text parsing (tools/cli.c):
 * cli_parse_numbers, cli_parse_double, cli_lines_next and
 * cli_line_is_blank_or_comment.
 *
 * The input is used twice: as one line (a buffer of exactly `size` bytes with
 * no NUL terminator, so ASan catches any read past the end), and as a file
 * read line by line through fmemopen, the way geom-bary reads its input.
 * Besides memory errors, it checks the parser's contract and aborts on a
 * violation:
 *  - the status is one the header documents, the count never exceeds max and
 *    an error names a column inside the line (1..size+1);
 *  - on success, the count equals the number of fields found by an
 *    independent split of the text on whitespace and commas, every value is
 *    finite unless non-finite values were allowed, and every value printed
 *    with "%.17g" parses back to the same bits;
 *  - allowing NaN/Inf never rejects a line the strict mode accepts, and
 *    gives the same values;
 *  - a smaller max gives the same prefix of values or GEOM_ERR_LIMIT.
 * and over core's geom_parse_double / geom_format_double: the number read
 * from the start of the bytes never reads past their end, equals glibc's
 * strtod (correctly rounded) on a copy of the prefix it consumed, and
 * formats to a string that parses back to the same bits.
 * Built as a libFuzzer binary with -DGEOM_FUZZ=ON (clang), and in every build
 * with driver.c, which runs the seed corpus tests/fuzz/corpus/numbers.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <float.h>
#include <math.h>

#include "cli.h"
#include "geom/core.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);       \
            abort();                                                                       \
        }                                                                                  \
    } while (0)

enum { MAX_VALUES = 64, SMALL_MAX = 12 };

static int is_sep(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f' ||
           c == ',';
}

/* Number of maximal runs of non-separator bytes. */
static size_t count_fields(const char *s, size_t len)
{
    size_t n = 0;
    for (size_t i = 0; i < len; i++)
        if (!is_sep(s[i]) && (i == 0 || is_sep(s[i - 1])))
            n++;
    return n;
}

static void check_roundtrip(double v)
{
    char buf[64];
    int k = snprintf(buf, sizeof buf, "%.17g", v);
    CHECK(k > 0 && (size_t)k < sizeof buf);
    double w;
    geom_diag d;
    geom_status st = cli_parse_double(buf, (size_t)k, CLI_NUM_ALLOW_NONFINITE, &w, &d);
    CHECK(st == GEOM_OK);
    if (isnan(v))
        CHECK(isnan(w));
    else
        CHECK(memcmp(&v, &w, sizeof v) == 0);
}

static void check_line(const char *s, size_t len)
{
    double strict[MAX_VALUES], loose[MAX_VALUES], few[SMALL_MAX];
    size_t n_strict = 99999, n_loose = 99999, n_few = 99999;
    geom_diag d;
    memset(&d, 0, sizeof d);

    geom_status st = cli_parse_numbers(s, len, 0, strict, MAX_VALUES, &n_strict, &d);
    CHECK(st == GEOM_OK || st == GEOM_ERR_PARSE || st == GEOM_ERR_LIMIT || st == GEOM_ERR_NOMEM);
    CHECK(n_strict <= MAX_VALUES);
    if (st != GEOM_OK) {
        CHECK(d.status == st);
        CHECK(d.column >= 1 && d.column <= len + 1);
        CHECK(d.message[0] != '\0');
        CHECK(memchr(d.message, '\0', sizeof d.message) != NULL);
    } else {
        CHECK(n_strict == count_fields(s, len));
        for (size_t i = 0; i < n_strict; i++) {
            CHECK(isfinite(strict[i]));
            check_roundtrip(strict[i]);
        }
    }

    geom_status st2 = cli_parse_numbers(s, len, CLI_NUM_ALLOW_NONFINITE, loose, MAX_VALUES,
                                        &n_loose, NULL);
    CHECK(n_loose <= MAX_VALUES);
    if (st == GEOM_OK) {
        CHECK(st2 == GEOM_OK && n_loose == n_strict);
        CHECK(n_strict == 0 || memcmp(strict, loose, n_strict * sizeof *strict) == 0);
    }
    if (st2 == GEOM_OK)
        for (size_t i = 0; i < n_loose; i++)
            check_roundtrip(loose[i]);

    geom_status st3 = cli_parse_numbers(s, len, 0, few, SMALL_MAX, &n_few, &d);
    CHECK(n_few <= SMALL_MAX);
    if (st == GEOM_OK && n_strict <= SMALL_MAX) {
        CHECK(st3 == GEOM_OK && n_few == n_strict);
    } else if (st == GEOM_OK) {
        CHECK(st3 == GEOM_ERR_LIMIT && n_few == SMALL_MAX);
        CHECK(d.column >= 1 && d.column <= len);
    }
    if (st3 == GEOM_OK || st3 == GEOM_ERR_LIMIT)
        CHECK(n_few == 0 || memcmp(few, strict, n_few * sizeof *few) == 0);

    (void)cli_line_is_blank_or_comment(s, len);
}

static void check_core(const char *s, size_t len)
{
    double v = 0.0;
    const char *stop = NULL;
    geom_status st = geom_parse_double(s, s + len, &v, &stop);
    CHECK(stop >= s && stop <= s + len);
    if (st == GEOM_ERR_PARSE) {
        CHECK(stop == s && v == 0.0);
        return;
    }
    CHECK(st == GEOM_OK || st == GEOM_ERR_DOMAIN);
    CHECK(stop > s);
    CHECK(st != GEOM_ERR_DOMAIN || isinf(v));
    size_t n = (size_t)(stop - s);
    char *copy = malloc(n + 1);
    if (!copy)
        return;
    memcpy(copy, s, n);
    copy[n] = '\0';
    char *end = NULL;
    double ref = strtod(copy, &end);
    CHECK(end == copy + n);
    /* glibc 2.36 misrounds some hexadecimal subnormals: not a reference there */
    int hex_subnormal = memchr(copy, 'x', n) || memchr(copy, 'X', n) ? fabs(ref) < DBL_MIN : 0;
    if (isnan(ref))
        CHECK(isnan(v));
    else if (!hex_subnormal)
        CHECK(memcmp(&ref, &v, sizeof v) == 0);
    free(copy);
    char buf[GEOM_DOUBLE_CHARS];
    size_t k = geom_format_double(v, buf);
    CHECK(k == strlen(buf) && k <= 24);
    double w = 1.0;
    CHECK(geom_parse_double(buf, buf + k, &w, &stop) == GEOM_OK && stop == buf + k);
    if (isnan(v))
        CHECK(isnan(w));
    else
        CHECK(memcmp(&v, &w, sizeof v) == 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* Exactly `size` bytes, not NUL-terminated. */
    char *buf = calloc(size ? size : 1, 1);
    if (!buf)
        return 0;
    if (size)
        memcpy(buf, data, size);
    check_line(buf, size);
    check_core(buf, size);

    /* The same bytes as a file, line by line. */
    if (size > 0) {
        FILE *fp = fmemopen(buf, size, "rb");
        if (fp) {
            cli_lines lines;
            cli_lines_init(&lines, fp, "<fuzz>");
            char *line;
            size_t len, total = 0;
            geom_diag d;
            int r;
            while ((r = cli_lines_next(&lines, &line, &len, &d)) > 0) {
                CHECK(line[len] == '\0');
                CHECK(memchr(line, '\n', len) == NULL);
                CHECK(memchr(line, '\0', len) == NULL);
                total += len;
                CHECK(total <= size);
                if (!cli_line_is_blank_or_comment(line, len))
                    check_line(line, len);
            }
            if (r < 0) {
                CHECK(r == GEOM_ERR_PARSE || r == GEOM_ERR_IO || r == GEOM_ERR_NOMEM);
                if (r == GEOM_ERR_PARSE) /* the NUL byte */
                    CHECK(memchr(data, '\0', size) != NULL && d.line >= 1 && d.column >= 1);
            } else {
                CHECK(memchr(data, '\0', size) == NULL);
            }
            cli_lines_free(&lines);
            fclose(fp);
        }
    }
    free(buf);
    return 0;
}
