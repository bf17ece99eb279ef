/* meshio helpers: numbers, text lines (growable arrays and the hash index
 * are core's: core/grow.c, core/hash.c). */
#include "meshio/meshio_internal.h"

#include <stdio.h>
#include <stdlib.h>

/* ---------------------------------------------------------------- numbers */

static int is_digit(char ch) { return ch >= '0' && ch <= '9'; }

int geom__meshio_parse_double(const char *s, size_t len, double *out)
{
    /* mesh files hold decimal numbers only: no "0x" (core reads them) */
    if ((len > 1 && (s[1] | 0x20) == 'x') || (len > 2 && (s[2] | 0x20) == 'x'))
        return -1;
    const char *stop;
    geom_status st = geom_parse_double(s, s + len, out, &stop);
    if (stop != s + len || (st == GEOM_OK && !isfinite(*out)))
        return -1;
    return st == GEOM_OK ? 0 : -2;
}

int geom__meshio_parse_int64(const char *s, size_t len, int64_t *out)
{
    size_t i = 0;
    int neg = 0;
    if (i < len && (s[i] == '+' || s[i] == '-')) {
        neg = s[i] == '-';
        i++;
    }
    if (i >= len)
        return -1;
    uint64_t v = 0;
    int big = 0;
    for (; i < len; i++) {
        if (!is_digit(s[i]))
            return -1;
        if (v > (UINT64_MAX - 9) / 10)
            big = 1;
        else
            v = v * 10 + (uint64_t)(s[i] - '0');
    }
    if (big || v > (uint64_t)INT64_MAX + (uint64_t)neg)
        return -2;
    *out = neg ? (int64_t)(0 - v) : (int64_t)v;
    return 0;
}

/* ------------------------------------------------------------- diagnostics */

geom_status geom__meshio_vdiag(geom_diag *d, geom_status st, const char *source, size_t line,
                               size_t col, const char *fmt, va_list ap)
{
    if (d) {
        char msg[GEOM_DIAG_MESSAGE_MAX]; /* first: an argument may point into d */
        vsnprintf(msg, sizeof msg, fmt, ap);
        geom__diag_set(d, st, source, line, col, "%s", msg);
    }
    return st;
}

geom_status geom__meshio_err_line(mio_ctx *c, geom_status st, size_t line, size_t col,
                                  const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    geom__meshio_vdiag(c->diag, st, c->source, line, col, fmt, ap);
    va_end(ap);
    return st;
}

geom_status geom__meshio_err_off(mio_ctx *c, geom_status st, uint64_t off, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    geom__meshio_vdiag(c->diag, st, c->source, 0, 0, fmt, ap);
    va_end(ap);
    if (c->diag)
        c->diag->byte_offset = off; /* as geom__diag_set_offset: no line or column */
    return st;
}

int geom__meshio_tok_ieq(const char *t, size_t tl, const char *word)
{
    size_t n = strlen(word);
    if (tl != n)
        return 0;
    for (size_t i = 0; i < n; i++) {
        char ch = t[i];
        if (ch >= 'A' && ch <= 'Z')
            ch = (char)(ch - 'A' + 'a');
        if (ch != word[i])
            return 0;
    }
    return 1;
}

/* ------------------------------------------------------------- text lines */

void geom__meshio_lines_init(mio_lines *l, const void *data, size_t size, int join_backslash)
{
    memset(l, 0, sizeof *l);
    l->data = data;
    l->size = size;
    l->next_lineno = 1;
    l->join_backslash = join_backslash;
}

void geom__meshio_lines_free(mio_lines *l, const geom_allocator *a) { MIO_FREE(a, l->join); }

/* One physical line from l->pos: text in [b, e), without the line end. */
static int phys_line(mio_lines *l, size_t *b, size_t *e)
{
    if (l->pos >= l->size)
        return 0;
    size_t start = l->pos;
    const char *nl = memchr(l->data + start, '\n', l->size - start);
    size_t end = nl ? (size_t)(nl - l->data) : l->size;
    l->pos = nl ? end + 1 : l->size;
    if (end > start && l->data[end - 1] == '\r')
        end--;
    *b = start;
    *e = end;
    l->next_lineno++;
    return 1;
}

int geom__meshio_lines_next(mio_lines *l, const geom_allocator *a, const char **s, size_t *len)
{
    size_t b, e;
    l->lineno = l->next_lineno;
    if (!phys_line(l, &b, &e))
        return 0;
    if (!l->join_backslash || e == b || l->data[e - 1] != '\\') {
        *s = l->data + b;
        *len = e - b;
        return 1;
    }
    /* joined line: copy the pieces, each backslash replaced by a space */
    l->join.n = 0;
    for (;;) {
        int cont = e > b && l->data[e - 1] == '\\';
        size_t n = e - b - (cont ? 1 : 0);
        if (MIO_RESERVE(a, l->join, n + 1) != GEOM_OK)
            return GEOM_ERR_NOMEM;
        memcpy(l->join.p + l->join.n, l->data + b, n);
        l->join.n += n;
        if (!cont)
            break;
        l->join.p[l->join.n++] = ' ';
        if (!phys_line(l, &b, &e))
            break;
    }
    *s = l->join.p;
    *len = l->join.n;
    return 1;
}

int geom__meshio_cursor_next(mio_cursor *cur, const char **t, size_t *tl, size_t *line,
                             size_t *col)
{
    size_t i = cur->pos;
    while (i < cur->size && mio_is_space(cur->data[i])) {
        if (cur->data[i] == '\n') {
            cur->line++;
            cur->line_start = i + 1;
        }
        i++;
    }
    if (i >= cur->size) {
        cur->pos = i;
        *line = cur->line;
        *col = i - cur->line_start + 1;
        return 0;
    }
    size_t b = i;
    while (i < cur->size && !mio_is_space(cur->data[i]))
        i++;
    *t = cur->data + b;
    *tl = i - b;
    *line = cur->line;
    *col = b - cur->line_start + 1;
    cur->pos = i;
    return 1;
}
