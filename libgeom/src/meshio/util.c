/* meshio helpers: growable arrays, hash index, numbers, text lines. */
#include "meshio/meshio_internal.h"

#include <stdio.h>
#include <stdlib.h>

/* ------------------------------------------------------- growable arrays */

geom_status geom_meshio__grow(const geom_allocator *a, void **p, size_t *cap, size_t need,
                              size_t elem)
{
    if (need <= *cap)
        return GEOM_OK;
    size_t ncap = *cap < 16 ? 16 : *cap;
    while (ncap < need) {
        if (ncap > SIZE_MAX / 2)
            return GEOM_ERR_LIMIT;
        ncap *= 2;
    }
    size_t bytes, old;
    if (geom_size_mul(ncap, elem, &bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    old = *cap * elem;
    void *q = geom_realloc(a, *p, old, bytes);
    if (!q)
        return GEOM_ERR_NOMEM;
    *p = q;
    *cap = ncap;
    return GEOM_OK;
}

/* ------------------------------------------------------------ hash index */

uint64_t geom_meshio__mix(uint64_t h, uint64_t v)
{
    /* splitmix64 finaliser over the running value */
    uint64_t z = h ^ (v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2));
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static void hash_put(uint64_t *slot, size_t cap, uint64_t e)
{
    size_t mask = cap - 1;
    /* the start slot depends only on the stored high half (see hash_start) */
    size_t i = (size_t)(((e >> 32) * 0x9e3779b97f4a7c15ull) >> 20) & mask;
    while (slot[i])
        i = (i + 1) & mask;
    slot[i] = e;
}

geom_status geom_meshio__hash_reserve(mio_hash *h, const geom_allocator *a, size_t n)
{
    if (n <= h->cap / 2 && h->cap)
        return GEOM_OK;
    size_t cap = h->cap ? h->cap : 64;
    while (cap / 2 < n) {
        if (cap > SIZE_MAX / 4)
            return GEOM_ERR_LIMIT;
        cap *= 2;
    }
    size_t bytes;
    if (geom_size_mul(cap, sizeof(uint64_t), &bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    uint64_t *s = geom_alloc(a, bytes);
    if (!s)
        return GEOM_ERR_NOMEM;
    memset(s, 0, bytes);
    for (size_t i = 0; i < h->cap; i++)
        if (h->slot[i])
            hash_put(s, cap, h->slot[i]);
    geom_free(a, h->slot, h->cap * sizeof(uint64_t));
    h->slot = s;
    h->cap = cap;
    return GEOM_OK;
}

static size_t hash_start(const mio_hash *h, uint64_t hash)
{
    uint64_t hi = hash >> 32;
    return (size_t)((hi * 0x9e3779b97f4a7c15ull) >> 20) & (h->cap - 1);
}

uint32_t geom_meshio__hash_next(const mio_hash *h, uint64_t hash, size_t *it)
{
    if (!h->cap)
        return UINT32_MAX;
    size_t mask = h->cap - 1;
    /* *it counts probes already made; the slot is start + *it */
    size_t i = (hash_start(h, hash) + *it) & mask;
    uint64_t hi = hash >> 32;
    for (;;) {
        uint64_t e = h->slot[i];
        if (!e) {
            return UINT32_MAX;
        }
        (*it)++;
        i = (i + 1) & mask;
        if ((e >> 32) == hi)
            return (uint32_t)((e & 0xffffffffu) - 1);
    }
}

void geom_meshio__hash_insert_at(mio_hash *h, uint64_t hash, size_t it, uint32_t id)
{
    size_t mask = h->cap - 1;
    size_t i = (hash_start(h, hash) + it) & mask;
    while (h->slot[i]) /* the probe stopped at a free slot; stay safe anyway */
        i = (i + 1) & mask;
    h->slot[i] = ((hash >> 32) << 32) | ((uint64_t)id + 1);
    h->n++;
}

void geom_meshio__hash_free(mio_hash *h, const geom_allocator *a)
{
    geom_free(a, h->slot, h->cap * sizeof(uint64_t));
    h->slot = NULL;
    h->cap = h->n = 0;
}

/* ---------------------------------------------------------------- numbers */

static int is_digit(char ch) { return ch >= '0' && ch <= '9'; }

int geom_meshio__parse_double(const char *s, size_t len, double *out)
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

int geom_meshio__parse_int64(const char *s, size_t len, int64_t *out)
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

geom_status geom_meshio__err_line(mio_ctx *c, geom_status st, size_t line, size_t col,
                                  const char *fmt, ...)
{
    if (c->diag) {
        char msg[GEOM_DIAG_MESSAGE_MAX];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, sizeof msg, fmt, ap);
        va_end(ap);
        geom_diag_set(c->diag, st, c->source, line, col, "%s", msg);
    }
    return st;
}

geom_status geom_meshio__err_off(mio_ctx *c, geom_status st, uint64_t off, const char *fmt, ...)
{
    if (c->diag) {
        char msg[GEOM_DIAG_MESSAGE_MAX];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, sizeof msg, fmt, ap);
        va_end(ap);
        geom_diag_set_offset(c->diag, st, c->source, off, "%s", msg);
    }
    return st;
}

int geom_meshio__tok_ieq(const char *t, size_t tl, const char *word)
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

void geom_meshio__lines_init(mio_lines *l, const void *data, size_t size, int join_backslash)
{
    memset(l, 0, sizeof *l);
    l->data = data;
    l->size = size;
    l->next_lineno = 1;
    l->join_backslash = join_backslash;
}

void geom_meshio__lines_free(mio_lines *l, const geom_allocator *a) { MIO_FREE(a, l->join); }

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

int geom_meshio__lines_next(mio_lines *l, const geom_allocator *a, const char **s, size_t *len)
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

int geom_meshio__cursor_next(mio_cursor *cur, const char **t, size_t *tl, size_t *line,
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
