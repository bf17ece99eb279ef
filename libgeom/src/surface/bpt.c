/* Reader of the indexed Bezier patch format of Newell's teapot (.bpt). */
#include "surface/surface_internal.h"

#include <errno.h>
#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BPT_MAX_COUNT ((size_t)1 << 24)
#define BPT_MAX_ITEMS 16

typedef struct bpt_line {
    const char *text;
    size_t len;
    size_t lineno;
} bpt_line;

typedef struct bpt_reader {
    const char *data;
    size_t size, pos, lineno;
    const char *source;
    geom_diag *diag;
} bpt_reader;

/* Next line that is not blank or a comment; 0 at the end of the input. */
static int next_line(bpt_reader *r, bpt_line *out)
{
    while (r->pos < r->size) {
        size_t start = r->pos, end = start;
        while (end < r->size && r->data[end] != '\n')
            ++end;
        r->pos = end < r->size ? end + 1 : end;
        r->lineno++;
        size_t len = end - start;
        if (len && r->data[start + len - 1] == '\r')
            --len;
        size_t k = 0;
        while (k < len && (r->data[start + k] == ' ' || r->data[start + k] == '\t'))
            ++k;
        if (k == len || r->data[start + k] == '#')
            continue;
        out->text = r->data + start;
        out->len = len;
        out->lineno = r->lineno;
        return 1;
    }
    return 0;
}

static int is_digit(char c)
{
    return c >= '0' && c <= '9';
}

/* Strict decimal syntax: [+-]digits[.digits][(e|E)[+-]digits], also "5."
 * and ".5". */
static int valid_number(const char *t, size_t n)
{
    size_t i = 0, digits = 0;
    if (i < n && (t[i] == '+' || t[i] == '-'))
        ++i;
    while (i < n && is_digit(t[i]))
        ++i, ++digits;
    if (i < n && t[i] == '.') {
        ++i;
        while (i < n && is_digit(t[i]))
            ++i, ++digits;
    }
    if (!digits)
        return 0;
    if (i < n && (t[i] == 'e' || t[i] == 'E')) {
        ++i;
        if (i < n && (t[i] == '+' || t[i] == '-'))
            ++i;
        size_t ed = 0;
        while (i < n && is_digit(t[i]))
            ++i, ++ed;
        if (!ed)
            return 0;
    }
    return i == n;
}

/* Convert a token already checked by valid_number; 0 on overflow. */
static int convert(const char *t, size_t n, double *out)
{
    char buf[128];
    if (n >= sizeof buf)
        return 0;
    memcpy(buf, t, n);
    buf[n] = '\0';
    char *end;
    errno = 0;
    double v = strtod(buf, &end);
    if (end != buf + n) {
        /* a locale whose decimal point is not '.' */
        const char *dp = localeconv()->decimal_point;
        char *dot = strchr(buf, '.');
        if (dot && dp && dp[0] && !dp[1])
            *dot = dp[0];
        errno = 0;
        v = strtod(buf, &end);
        if (end != buf + n)
            return 0;
    }
    if (!isfinite(v))
        return 0;
    *out = v;
    return 1;
}

/* Split a line into up to max numbers separated by blanks and/or single
 * commas; exactly `want` are required. */
static geom_status parse_numbers(bpt_reader *r, const bpt_line *ln, size_t want, const char *what,
                                 double *vals)
{
    size_t i = 0, count = 0, n = ln->len;
    const char *t = ln->text;
    int need_value = 0; /* after a comma */
    for (;;) {
        while (i < n && (t[i] == ' ' || t[i] == '\t'))
            ++i;
        if (i >= n)
            break;
        if (t[i] == ',') {
            if (need_value || count == 0)
                return geom__diag_set(r->diag, GEOM_ERR_PARSE, r->source, ln->lineno, i + 1,
                                     "empty field before ',' in %s", what);
            need_value = 1;
            ++i;
            continue;
        }
        size_t s = i;
        while (i < n && t[i] != ' ' && t[i] != '\t' && t[i] != ',')
            ++i;
        if (count == want)
            return geom__diag_set(r->diag, GEOM_ERR_PARSE, r->source, ln->lineno, s + 1,
                                 "too many values in %s (%zu expected)", what, want);
        if (!valid_number(t + s, i - s) || !convert(t + s, i - s, &vals[count]))
            return geom__diag_set(r->diag, GEOM_ERR_PARSE, r->source, ln->lineno, s + 1,
                                 "invalid number '%.*s' in %s", (int)(i - s > 40 ? 40 : i - s),
                                 t + s, what);
        ++count;
        need_value = 0;
    }
    if (need_value)
        return geom__diag_set(r->diag, GEOM_ERR_PARSE, r->source, ln->lineno, n,
                             "trailing ',' in %s", what);
    if (count != want)
        return geom__diag_set(r->diag, GEOM_ERR_PARSE, r->source, ln->lineno, 1,
                             "%s has %zu values, %zu expected", what, count, want);
    return GEOM_OK;
}

static geom_status parse_count(bpt_reader *r, const char *what, size_t *out)
{
    bpt_line ln;
    if (!next_line(r, &ln))
        return geom__diag_set(r->diag, GEOM_ERR_PARSE, r->source, r->lineno, 0,
                             "unexpected end of input: %s expected", what);
    double v;
    geom_status st = parse_numbers(r, &ln, 1, what, &v);
    if (st != GEOM_OK)
        return st;
    if (v != floor(v) || v < 1.0)
        return geom__diag_set(r->diag, GEOM_ERR_PARSE, r->source, ln.lineno, 1,
                             "%s must be a positive integer, not %.17g", what, v);
    if (v > (double)BPT_MAX_COUNT)
        return geom__diag_set(r->diag, GEOM_ERR_LIMIT, r->source, ln.lineno, 1,
                             "%s %.17g is above the limit of %zu", what, v, BPT_MAX_COUNT);
    *out = (size_t)v;
    return GEOM_OK;
}

geom_status geom_surface_read_bpt_memory(const void *data, size_t size, const char *source_name,
                                         const geom_allocator *alloc, geom_surface_set **out,
                                         geom_diag *diag)
{
    if (!out || (!data && size))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "bpt: NULL argument");
    *out = NULL;
    bpt_reader r = {data, size, 0, 0, source_name ? source_name : "<memory>", diag};
    size_t np, nq;
    geom_status st = parse_count(&r, "the patch count", &np);
    if (st != GEOM_OK)
        return st;
    /* a patch line holds at least 31 bytes ("1,1,...,1"): reject counts
     * the input cannot hold before allocating */
    if (np > size / 31 + 1)
        return geom__diag_set(diag, GEOM_ERR_PARSE, r.source, r.lineno, 1,
                             "patch count %zu is larger than the input can hold", np);
    uint32_t *idx = geom__alloc(alloc, np * 16 * sizeof(uint32_t));
    if (!idx)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, r.source, 0, 0, "out of memory");
    size_t *idx_line = geom__alloc(alloc, np * sizeof(size_t));
    double *pts = NULL;
    size_t pts_bytes = 0;
    geom_surface_set *set = NULL;
    if (!idx_line) {
        st = geom__diag_set(diag, GEOM_ERR_NOMEM, r.source, 0, 0, "out of memory");
        goto done;
    }
    for (size_t k = 0; k < np; ++k) {
        bpt_line ln;
        if (!next_line(&r, &ln)) {
            st = geom__diag_set(diag, GEOM_ERR_PARSE, r.source, r.lineno, 0,
                               "unexpected end of input: patch %zu of %zu expected", k + 1, np);
            goto done;
        }
        double v[16];
        char what[48];
        snprintf(what, sizeof what, "patch %zu", k + 1);
        st = parse_numbers(&r, &ln, 16, what, v);
        if (st != GEOM_OK)
            goto done;
        for (int j = 0; j < 16; ++j) {
            if (v[j] != floor(v[j]) || v[j] < 1.0 || v[j] > (double)BPT_MAX_COUNT) {
                st = geom__diag_set(diag, GEOM_ERR_PARSE, r.source, ln.lineno, 1,
                                   "patch %zu: index %d is %.17g, not a point number >= 1", k + 1,
                                   j + 1, v[j]);
                goto done;
            }
            idx[16 * k + (size_t)j] = (uint32_t)v[j];
        }
        idx_line[k] = ln.lineno;
    }
    st = parse_count(&r, "the point count", &nq);
    if (st != GEOM_OK)
        goto done;
    if (nq > size / 6 + 1) {
        st = geom__diag_set(diag, GEOM_ERR_PARSE, r.source, r.lineno, 1,
                           "point count %zu is larger than the input can hold", nq);
        goto done;
    }
    pts_bytes = nq * 3 * sizeof(double);
    pts = geom__alloc(alloc, pts_bytes);
    if (!pts) {
        st = geom__diag_set(diag, GEOM_ERR_NOMEM, r.source, 0, 0, "out of memory");
        goto done;
    }
    for (size_t k = 0; k < nq; ++k) {
        bpt_line ln;
        if (!next_line(&r, &ln)) {
            st = geom__diag_set(diag, GEOM_ERR_PARSE, r.source, r.lineno, 0,
                               "unexpected end of input: point %zu of %zu expected", k + 1, nq);
            goto done;
        }
        char what[48];
        snprintf(what, sizeof what, "point %zu", k + 1);
        st = parse_numbers(&r, &ln, 3, what, pts + 3 * k);
        if (st != GEOM_OK)
            goto done;
    }
    {
        bpt_line ln;
        if (next_line(&r, &ln)) {
            st = geom__diag_set(diag, GEOM_ERR_PARSE, r.source, ln.lineno, 1,
                               "unexpected content after the %zu points", nq);
            goto done;
        }
    }
    for (size_t k = 0; k < np; ++k)
        for (int j = 0; j < 16; ++j)
            if (idx[16 * k + (size_t)j] > nq) {
                st = geom__diag_set(diag, GEOM_ERR_PARSE, r.source, idx_line[k], 1,
                                   "patch %zu: index %d is %u, but there are %zu points", k + 1,
                                   j + 1, idx[16 * k + (size_t)j], nq);
                goto done;
            }
    set = geom_surface_set_create(alloc);
    if (!set) {
        st = geom__diag_set(diag, GEOM_ERR_NOMEM, r.source, 0, 0, "out of memory");
        goto done;
    }
    for (size_t k = 0; k < np; ++k) {
        double P[48], ku[8], kv[8];
        /* item 4*r + c of the patch line is control point (i = c, j = r):
         * the rows of the 4 x 4 list run along u, which makes Newell's
         * patches face outward (Su x Sv) */
        for (int r4 = 0; r4 < 4; ++r4)
            for (int c4 = 0; c4 < 4; ++c4)
                memcpy(P + 3 * (4 * c4 + r4), pts + 3 * (idx[16 * k + (size_t)(4 * r4 + c4)] - 1),
                       3 * sizeof(double));
        geom_nurbs_surface s;
        geom_surface_bezier(3, 3, P, NULL, ku, kv, &s);
        char name[32];
        snprintf(name, sizeof name, "patch %zu", k + 1);
        st = geom_surface_set_add(set, &s, name);
        if (st != GEOM_OK) {
            geom__diag_set(diag, st, r.source, 0, 0, "out of memory");
            goto done;
        }
    }
    *out = set;
    set = NULL;
done:
    geom_surface_set_destroy(set);
    geom__free(alloc, pts, pts_bytes);
    geom__free(alloc, idx_line, np * sizeof(size_t));
    geom__free(alloc, idx, np * 16 * sizeof(uint32_t));
    return st;
}

geom_status geom_surface_read_bpt(const char *path, const geom_allocator *alloc,
                                  geom_surface_set **out, geom_diag *diag)
{
    if (!path || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "bpt: NULL argument");
    *out = NULL;
    geom_file f;
    geom_status st = geom_file_map(path, alloc, &f, diag);
    if (st == GEOM_OK)
        st = geom_surface_read_bpt_memory(f.data, f.size, path, alloc, out, diag);
    geom_file_unmap(&f);
    return st;
}
