/*
 * ISO 10303-21 exchange structure: a one-pass tokenizer and recursive
 * descent parser over the text into a flat instance table (entities, their
 * parts, parameter values in one array with list children contiguous, and
 * one string pool), then resolution of every #n reference to an entity
 * index through a hash on the ids. Errors carry line and column.
 */
#include "step/step_internal.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct lexer {
    const char *s;
    size_t n, i;
    size_t line, col;
    geom__p21 *p;
    geom_diag *diag;
    int max_depth;
    /* values being collected for the open lists */
    geom__p21_value *tmp;
    size_t ntmp, captmp;
} lexer;

#define GROW(ptr, n, cap, type, alloc)                                                     \
    do {                                                                                   \
        void *p_ = (ptr);                                                                  \
        geom_status st_ = geom__grow(alloc, &p_, &(cap), (n) + 1, sizeof(type));          \
        if (st_ != GEOM_OK)                                                                \
            return st_;                                                                    \
        (ptr) = p_;                                                                        \
    } while (0)

static geom_status err(lexer *L, geom_status st, const char *fmt, const char *arg)
{
    char msg[GEOM_DIAG_MESSAGE_MAX];
    snprintf(msg, sizeof msg, fmt, arg ? arg : "");
    return geom__diag_set(L->diag, st, L->p->source, L->line, L->col, "%s", msg);
}

static int peekc(const lexer *L)
{
    return L->i < L->n ? (unsigned char)L->s[L->i] : -1;
}

static void adv(lexer *L)
{
    if (L->i < L->n) {
        if (L->s[L->i] == '\n') {
            L->line++;
            L->col = 1;
        } else {
            L->col++;
        }
        L->i++;
    }
}

/* Skip white space and comments. */
static geom_status skip(lexer *L)
{
    for (;;) {
        int c = peekc(L);
        if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v') {
            adv(L);
        } else if (c == '/' && L->i + 1 < L->n && L->s[L->i + 1] == '*') {
            size_t l0 = L->line, c0 = L->col;
            adv(L);
            adv(L);
            for (;;) {
                if (L->i >= L->n) {
                    L->line = l0;
                    L->col = c0;
                    return err(L, GEOM_ERR_PARSE, "unterminated comment%s", NULL);
                }
                if (L->s[L->i] == '*' && L->i + 1 < L->n && L->s[L->i + 1] == '/') {
                    adv(L);
                    adv(L);
                    break;
                }
                adv(L);
            }
        } else {
            return GEOM_OK;
        }
    }
}

static geom_status pool_add(geom__p21 *p, const char *s, size_t len, uint64_t *off)
{
    if (p->npool + len + 1 > UINT32_MAX)
        return GEOM_ERR_LIMIT;
    geom_status st = geom__grow(p->alloc, (void **)&p->pool, &p->cappool, p->npool + len + 1, 1);
    if (st != GEOM_OK)
        return st;
    *off = p->npool;
    if (len)
        memcpy(p->pool + p->npool, s, len);
    p->pool[p->npool + len] = '\0';
    p->npool += len + 1;
    return GEOM_OK;
}

static int is_kw_start(int c)
{
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == '!';
}

static int is_kw(int c)
{
    return is_kw_start(c) || (c >= '0' && c <= '9') || c == '-';
}

/* A keyword (upper-cased into the pool). */
static geom_status keyword(lexer *L, uint64_t *off)
{
    size_t b = L->i;
    if (peekc(L) == '!')
        adv(L);
    while (is_kw(peekc(L)) && peekc(L) != '!')
        adv(L);
    size_t len = L->i - b;
    if (len == 0 || len > 1024)
        return err(L, GEOM_ERR_PARSE, "expected a keyword%s", NULL);
    char buf[1025];
    for (size_t k = 0; k < len; k++)
        buf[k] = (char)toupper((unsigned char)L->s[b + k]);
    return pool_add(L->p, buf, len, off);
}

static geom_status push_tmp(lexer *L, const geom__p21_value *v)
{
    GROW(L->tmp, L->ntmp, L->captmp, geom__p21_value, L->p->alloc);
    L->tmp[L->ntmp++] = *v;
    return GEOM_OK;
}

static int hexval(int c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    return -1;
}

/* The digits of an instance id after its '#' (already consumed). */
static geom_status instance_id(lexer *L, uint64_t *out)
{
    uint64_t id = 0;
    size_t d = 0;
    while (peekc(L) >= '0' && peekc(L) <= '9') {
        if (id > (UINT64_MAX - 9) / 10)
            return err(L, GEOM_ERR_PARSE, "instance id too large%s", NULL);
        id = id * 10 + (uint64_t)(peekc(L) - '0');
        adv(L), d++;
    }
    if (d == 0)
        return err(L, GEOM_ERR_PARSE, "'#' without an instance number%s", NULL);
    *out = id;
    return GEOM_OK;
}

/* Append code point cp as UTF-8 to buf (growable). */
static geom_status put_utf8(lexer *L, char **buf, size_t *len, size_t *cap, uint32_t cp)
{
    geom_status st = geom__grow(L->p->alloc, (void **)buf, cap, *len + 5, 1);
    if (st != GEOM_OK)
        return st;
    char *o = *buf + *len;
    if (cp < 0x80) {
        o[0] = (char)cp;
        *len += 1;
    } else if (cp < 0x800) {
        o[0] = (char)(0xC0 | (cp >> 6));
        o[1] = (char)(0x80 | (cp & 0x3F));
        *len += 2;
    } else if (cp < 0x10000) {
        o[0] = (char)(0xE0 | (cp >> 12));
        o[1] = (char)(0x80 | ((cp >> 6) & 0x3F));
        o[2] = (char)(0x80 | (cp & 0x3F));
        *len += 3;
    } else {
        if (cp > 0x10FFFF)
            cp = 0xFFFD;
        o[0] = (char)(0xF0 | (cp >> 18));
        o[1] = (char)(0x80 | ((cp >> 12) & 0x3F));
        o[2] = (char)(0x80 | ((cp >> 6) & 0x3F));
        o[3] = (char)(0x80 | (cp & 0x3F));
        *len += 4;
    }
    return GEOM_OK;
}

/* Read `digits` hex digits into *v; error if any is not hex. */
static int read_hex(lexer *L, int digits, uint32_t *v)
{
    uint32_t x = 0;
    for (int k = 0; k < digits; k++) {
        int h = L->i < L->n ? hexval((unsigned char)L->s[L->i]) : -1;
        if (h < 0)
            return 0;
        x = x * 16 + (uint32_t)h;
        adv(L);
    }
    *v = x;
    return 1;
}

static int at(const lexer *L, const char *lit)
{
    size_t k = strlen(lit);
    return L->i + k <= L->n && memcmp(L->s + L->i, lit, k) == 0;
}

/* A string literal '...' with its escapes, decoded to UTF-8. */
static geom_status string_lit(lexer *L, uint64_t *off, uint32_t *outlen)
{
    size_t l0 = L->line, c0 = L->col;
    adv(L); /* opening quote */
    char *buf = NULL;
    size_t len = 0, cap = 0;
    geom_status st = GEOM_OK;
    for (;;) {
        if (L->i >= L->n) {
            L->line = l0;
            L->col = c0;
            st = err(L, GEOM_ERR_PARSE, "unterminated string%s", NULL);
            break;
        }
        int c = (unsigned char)L->s[L->i];
        if (c == '\'') {
            adv(L);
            if (peekc(L) == '\'') {
                adv(L);
                st = put_utf8(L, &buf, &len, &cap, '\'');
            } else {
                break;
            }
        } else if (c == '\\') {
            uint32_t v;
            if (at(L, "\\\\")) {
                adv(L);
                adv(L);
                st = put_utf8(L, &buf, &len, &cap, '\\');
            } else if (at(L, "\\X\\")) {
                for (int k = 0; k < 3; k++)
                    adv(L);
                if (!read_hex(L, 2, &v)) {
                    st = err(L, GEOM_ERR_PARSE, "bad \\X\\ escape: two hex digits expected%s", NULL);
                    break;
                }
                st = put_utf8(L, &buf, &len, &cap, v);
            } else if (at(L, "\\X2\\") || at(L, "\\X4\\")) {
                int digits = L->s[L->i + 2] == '2' ? 4 : 8;
                for (int k = 0; k < 4; k++)
                    adv(L);
                while (!at(L, "\\X0\\")) {
                    if (!read_hex(L, digits, &v)) {
                        st = err(L, GEOM_ERR_PARSE, "bad \\X2\\ or \\X4\\ escape (hex groups ended by \\X0\\)%s", NULL);
                        break;
                    }
                    if ((st = put_utf8(L, &buf, &len, &cap, v)) != GEOM_OK)
                        break;
                }
                if (st != GEOM_OK)
                    break;
                for (int k = 0; k < 4; k++)
                    adv(L);
            } else if (at(L, "\\S\\") && L->i + 3 < L->n) {
                for (int k = 0; k < 3; k++)
                    adv(L);
                v = (uint32_t)(unsigned char)L->s[L->i] + 128;
                adv(L);
                st = put_utf8(L, &buf, &len, &cap, v);
            } else if (at(L, "\\P") && L->i + 3 < L->n && L->s[L->i + 3] == '\\') {
                for (int k = 0; k < 4; k++) /* code page switch: ignored (ISO 8859-1 assumed) */
                    adv(L);
            } else if (at(L, "\\N\\")) {
                for (int k = 0; k < 3; k++)
                    adv(L);
                st = put_utf8(L, &buf, &len, &cap, '\n');
            } else if (at(L, "\\T\\")) {
                for (int k = 0; k < 3; k++)
                    adv(L);
                st = put_utf8(L, &buf, &len, &cap, '\t');
            } else {
                st = err(L, GEOM_ERR_PARSE, "unknown escape in string%s", NULL);
            }
        } else if (c == '\n' || c == '\r') {
            adv(L); /* line breaks inside strings are not part of the value */
        } else {
            adv(L);
            if (c >= 0x80) {
                /* already UTF-8 (AP242 edition 3 allows it): copy the byte */
                if (len + 4 >= cap)
                    st = put_utf8(L, &buf, &len, &cap, 'x'), len--;
                if (st == GEOM_OK)
                    buf[len++] = (char)c;
            } else {
                st = put_utf8(L, &buf, &len, &cap, (uint32_t)c);
            }
        }
        if (st != GEOM_OK)
            break;
    }
    if (st == GEOM_OK) {
        if (len > UINT32_MAX - 1)
            st = GEOM_ERR_LIMIT;
        else
            st = pool_add(L->p, buf ? buf : "", len, off);
        *outlen = (uint32_t)len;
    }
    geom__free(L->p->alloc, buf, cap);
    return st;
}

static geom_status value(lexer *L, int depth);

/* '(' values ',' ... ')' onto tmp as one LIST value. */
static geom_status list(lexer *L, int depth)
{
    if (depth > L->max_depth)
        return err(L, GEOM_ERR_LIMIT, "parameter lists nested too deeply%s", NULL);
    adv(L); /* ( */
    size_t mark = L->ntmp;
    geom_status st = skip(L);
    if (st)
        return st;
    if (peekc(L) != ')') {
        for (;;) {
            if ((st = value(L, depth + 1)) != GEOM_OK)
                return st;
            if ((st = skip(L)) != GEOM_OK)
                return st;
            int c = peekc(L);
            if (c == ',') {
                adv(L);
                if ((st = skip(L)) != GEOM_OK)
                    return st;
                continue;
            }
            if (c == ')')
                break;
            return err(L, GEOM_ERR_PARSE, "expected ',' or ')' in a parameter list%s", NULL);
        }
    }
    adv(L); /* ) */
    geom__p21 *p = L->p;
    size_t cnt = L->ntmp - mark;
    if (p->nvals + cnt > UINT32_MAX - 1)
        return err(L, GEOM_ERR_LIMIT, "too many parameter values%s", NULL);
    st = geom__grow(p->alloc, (void **)&p->vals, &p->capvals, p->nvals + cnt, sizeof *p->vals);
    if (st != GEOM_OK)
        return st;
    geom__p21_value lv;
    memset(&lv, 0, sizeof lv);
    lv.kind = GEOM__P21_LIST;
    lv.off = p->nvals;
    lv.n = (uint32_t)cnt;
    if (cnt)
        memcpy(p->vals + p->nvals, L->tmp + mark, cnt * sizeof *L->tmp);
    p->nvals += cnt;
    L->ntmp = mark;
    return push_tmp(L, &lv);
}

static geom_status number(lexer *L, geom__p21_value *v)
{
    size_t b = L->i;
    int real = 0;
    if (peekc(L) == '+' || peekc(L) == '-')
        adv(L);
    size_t digits = 0;
    while (peekc(L) >= '0' && peekc(L) <= '9')
        adv(L), digits++;
    if (peekc(L) == '.') {
        real = 1;
        adv(L);
        while (peekc(L) >= '0' && peekc(L) <= '9')
            adv(L), digits++;
    }
    if (digits == 0)
        return err(L, GEOM_ERR_PARSE, "malformed number%s", NULL);
    if (peekc(L) == 'E' || peekc(L) == 'e') {
        real = 1;
        adv(L);
        if (peekc(L) == '+' || peekc(L) == '-')
            adv(L);
        size_t ed = 0;
        while (peekc(L) >= '0' && peekc(L) <= '9')
            adv(L), ed++;
        if (ed == 0)
            return err(L, GEOM_ERR_PARSE, "malformed exponent%s", NULL);
    }
    size_t len = L->i - b;
    char buf[128];
    if (len >= sizeof buf)
        return err(L, GEOM_ERR_PARSE, "number too long%s", NULL);
    memcpy(buf, L->s + b, len);
    buf[len] = '\0';
    memset(v, 0, sizeof *v);
    if (real) {
        v->kind = GEOM__P21_REAL;
        v->u.r = strtod(buf, NULL);
        if (!isfinite(v->u.r))
            return err(L, GEOM_ERR_PARSE, "number out of range: %s", buf);
    } else {
        errno = 0;
        long long x = strtoll(buf, NULL, 10);
        if (errno == ERANGE) {
            v->kind = GEOM__P21_REAL;
            v->u.r = strtod(buf, NULL);
        } else {
            v->kind = GEOM__P21_INT;
            v->u.i = x;
        }
    }
    return GEOM_OK;
}

static geom_status value(lexer *L, int depth)
{
    geom__p21_value v;
    memset(&v, 0, sizeof v);
    geom_status st;
    int c = peekc(L);
    if (c == '(')
        return list(L, depth);
    if (c == '$') {
        adv(L);
        v.kind = GEOM__P21_NULL;
    } else if (c == '*') {
        adv(L);
        v.kind = GEOM__P21_DERIVED;
    } else if (c == '#') {
        v.kind = GEOM__P21_REF;
        v.n = (uint32_t)(L->line > UINT32_MAX ? UINT32_MAX : L->line);
        v.off = L->col;
        adv(L);
        if ((st = instance_id(L, &v.u.ref)) != GEOM_OK)
            return st;
    } else if (c == '\'') {
        v.kind = GEOM__P21_STRING;
        if ((st = string_lit(L, &v.off, &v.n)) != GEOM_OK)
            return st;
    } else if (c == '"') {
        adv(L);
        size_t b = L->i;
        while (L->i < L->n && hexval((unsigned char)L->s[L->i]) >= 0)
            adv(L);
        if (peekc(L) != '"')
            return err(L, GEOM_ERR_PARSE, "malformed binary literal%s", NULL);
        v.kind = GEOM__P21_BINARY;
        if ((st = pool_add(L->p, L->s + b, L->i - b, &v.off)) != GEOM_OK)
            return st;
        adv(L);
    } else if (c == '.') {
        adv(L);
        size_t b = L->i;
        while (is_kw(peekc(L)) && peekc(L) != '!')
            adv(L);
        if (peekc(L) != '.' || L->i == b)
            return err(L, GEOM_ERR_PARSE, "malformed enumeration (expected .NAME.)%s", NULL);
        char buf[257];
        size_t len = L->i - b;
        if (len > 256)
            return err(L, GEOM_ERR_PARSE, "enumeration too long%s", NULL);
        for (size_t k = 0; k < len; k++)
            buf[k] = (char)toupper((unsigned char)L->s[b + k]);
        adv(L);
        v.kind = GEOM__P21_ENUM;
        if ((st = pool_add(L->p, buf, len, &v.off)) != GEOM_OK)
            return st;
    } else if (c == '+' || c == '-' || (c >= '0' && c <= '9')) {
        if ((st = number(L, &v)) != GEOM_OK)
            return st;
    } else if (is_kw_start(c)) {
        /* typed parameter: KEYWORD '(' value ')' */
        uint64_t name;
        if ((st = keyword(L, &name)) != GEOM_OK)
            return st;
        if ((st = skip(L)) != GEOM_OK)
            return st;
        if (peekc(L) != '(')
            return err(L, GEOM_ERR_PARSE, "expected '(' after a typed parameter's type%s", NULL);
        if (depth > L->max_depth)
            return err(L, GEOM_ERR_LIMIT, "parameter lists nested too deeply%s", NULL);
        if ((st = list(L, depth + 1)) != GEOM_OK)
            return st;
        geom__p21_value lv = L->tmp[--L->ntmp];
        if (lv.n != 1)
            return err(L, GEOM_ERR_PARSE, "a typed parameter holds exactly one value%s", NULL);
        v.kind = GEOM__P21_TYPED;
        v.u.name = name;
        v.off = lv.off;
        v.n = 1;
    } else if (c < 0) {
        return err(L, GEOM_ERR_PARSE, "unexpected end of input in a parameter list%s", NULL);
    } else {
        char ch[2] = {(char)c, 0};
        return err(L, GEOM_ERR_PARSE, "unexpected character '%s' in a parameter list",
                   isprint(c) ? ch : "?");
    }
    return push_tmp(L, &v);
}

/* One part: KEYWORD '(' params ')' appended to parts. */
static geom_status part(lexer *L)
{
    uint64_t name;
    geom_status st = keyword(L, &name);
    if (st)
        return st;
    if ((st = skip(L)) != GEOM_OK)
        return st;
    if (peekc(L) != '(')
        return err(L, GEOM_ERR_PARSE, "expected '(' after an entity type%s", NULL);
    if ((st = list(L, 1)) != GEOM_OK)
        return st;
    geom__p21_value lv = L->tmp[--L->ntmp];
    geom__p21 *p = L->p;
    /* the argument list itself becomes a value */
    GROW(p->vals, p->nvals, p->capvals, geom__p21_value, p->alloc);
    GROW(p->parts, p->nparts, p->capparts, geom__p21_part_t, p->alloc);
    if (p->nvals >= UINT32_MAX - 1 || p->nparts >= UINT32_MAX - 1)
        return err(L, GEOM_ERR_LIMIT, "too many instances%s", NULL);
    p->vals[p->nvals] = lv;
    p->parts[p->nparts].name = (uint32_t)name;
    p->parts[p->nparts].args = (uint32_t)p->nvals;
    p->nvals++;
    p->nparts++;
    return GEOM_OK;
}

static geom_status expect(lexer *L, int ch, const char *what)
{
    geom_status st = skip(L);
    if (st)
        return st;
    if (peekc(L) != ch)
        return err(L, GEOM_ERR_PARSE, "expected %s", what);
    adv(L);
    return GEOM_OK;
}

/* An instance after its '#id' or a header entity: '=' simple | complex, ';'. */
static geom_status instance(lexer *L, uint64_t id, size_t line, size_t col, int header)
{
    geom__p21 *p = L->p;
    geom_status st;
    if (!header && (st = expect(L, '=', "'=' after the instance name")) != GEOM_OK)
        return st;
    if ((st = skip(L)) != GEOM_OK)
        return st;
    uint32_t first = (uint32_t)p->nparts;
    if (peekc(L) == '(' && !header) {
        adv(L);
        for (;;) {
            if ((st = skip(L)) != GEOM_OK)
                return st;
            if (peekc(L) == ')') {
                adv(L);
                break;
            }
            if (!is_kw_start(peekc(L)))
                return err(L, GEOM_ERR_PARSE, "expected an entity type or ')' in a complex instance%s", NULL);
            if ((st = part(L)) != GEOM_OK)
                return st;
        }
        if (p->nparts == first)
            return err(L, GEOM_ERR_PARSE, "empty complex instance%s", NULL);
    } else if (is_kw_start(peekc(L))) {
        if ((st = part(L)) != GEOM_OK)
            return st;
    } else {
        return err(L, GEOM_ERR_PARSE, "expected an entity type after '='%s", NULL);
    }
    if ((st = expect(L, ';', "';' after an instance")) != GEOM_OK)
        return st;
    GROW(p->ents, p->nents, p->capents, geom__p21_entity, p->alloc);
    geom__p21_entity *e = &p->ents[p->nents++];
    e->id = id;
    e->first_part = first;
    e->nparts = (uint32_t)(p->nparts - first);
    e->line = (uint32_t)(line > UINT32_MAX ? UINT32_MAX : line);
    e->column = (uint32_t)(col > UINT32_MAX ? UINT32_MAX : col);
    return GEOM_OK;
}

uint32_t geom__p21_find(const geom__p21 *p, uint64_t id)
{
    uint64_t h = geom__hash_mix(0, id);
    size_t it = 0;
    uint32_t e;
    while ((e = geom__hindex_next(&p->hash, h, &it)) != UINT32_MAX)
        if (p->ents[e].id == id)
            return e;
    return UINT32_MAX;
}

static geom_status build_hash(lexer *L)
{
    geom__p21 *p = L->p;
    geom_status st = geom__hindex_reserve(&p->hash, p->alloc, p->nents);
    if (st != GEOM_OK)
        return st;
    for (size_t k = p->nheader; k < p->nents; k++) {
        uint64_t id = p->ents[k].id;
        uint64_t h = geom__hash_mix(0, id);
        size_t it = 0;
        uint32_t e;
        while ((e = geom__hindex_next(&p->hash, h, &it)) != UINT32_MAX)
            if (p->ents[e].id == id) {
                char msg[64];
                snprintf(msg, sizeof msg, "#%llu", (unsigned long long)id);
                L->line = p->ents[k].line;
                L->col = p->ents[k].column;
                return err(L, GEOM_ERR_PARSE, "instance %s defined twice", msg);
            }
        geom__hindex_insert_at(&p->hash, h, it, (uint32_t)k);
    }
    /* resolve references */
    for (size_t k = 0; k < p->nvals; k++) {
        geom__p21_value *v = &p->vals[k];
        if (v->kind != GEOM__P21_REF)
            continue;
        uint32_t e = geom__p21_find(p, v->u.ref);
        if (e == UINT32_MAX) {
            char msg[64];
            snprintf(msg, sizeof msg, "#%llu", (unsigned long long)v->u.ref);
            L->line = v->n;
            L->col = (size_t)v->off;
            return err(L, GEOM_ERR_PARSE, "dangling reference: %s is never defined", msg);
        }
        v->u.ref = e;
    }
    return GEOM_OK;
}

static geom_status section_kw(lexer *L, const char *want)
{
    geom_status st = skip(L);
    if (st)
        return st;
    size_t k = strlen(want);
    if (!at(L, want) || (L->i + k < L->n && is_kw((unsigned char)L->s[L->i + k])))
        return err(L, GEOM_ERR_PARSE, "expected '%s'", want);
    for (size_t j = 0; j < k; j++)
        adv(L);
    return GEOM_OK;
}

static geom_status parse_all(lexer *L)
{
    geom__p21 *p = L->p;
    geom_status st;
    if ((st = section_kw(L, "ISO-10303-21")) != GEOM_OK)
        return st;
    if ((st = expect(L, ';', "';' after ISO-10303-21")) != GEOM_OK)
        return st;
    if ((st = section_kw(L, "HEADER")) != GEOM_OK)
        return st;
    if ((st = expect(L, ';', "';' after HEADER")) != GEOM_OK)
        return st;
    for (;;) {
        if ((st = skip(L)) != GEOM_OK)
            return st;
        if (at(L, "ENDSEC"))
            break;
        if (!is_kw_start(peekc(L)))
            return err(L, GEOM_ERR_PARSE, "expected a header entity or ENDSEC%s", NULL);
        if ((st = instance(L, 0, L->line, L->col, 1)) != GEOM_OK)
            return st;
    }
    p->nheader = p->nents;
    if ((st = section_kw(L, "ENDSEC")) != GEOM_OK)
        return st;
    if ((st = expect(L, ';', "';' after ENDSEC")) != GEOM_OK)
        return st;
    int ndata = 0;
    for (;;) {
        if ((st = skip(L)) != GEOM_OK)
            return st;
        if (at(L, "END-ISO-10303-21"))
            break;
        if (!at(L, "DATA"))
            return err(L, GEOM_ERR_PARSE, "expected DATA or END-ISO-10303-21%s", NULL);
        if ((st = section_kw(L, "DATA")) != GEOM_OK)
            return st;
        ndata++;
        if ((st = skip(L)) != GEOM_OK)
            return st;
        if (peekc(L) == '(') { /* DATA(name, schemas) of edition 3 */
            if ((st = list(L, 1)) != GEOM_OK)
                return st;
            L->ntmp--;
        }
        if ((st = expect(L, ';', "';' after DATA")) != GEOM_OK)
            return st;
        for (;;) {
            if ((st = skip(L)) != GEOM_OK)
                return st;
            int c = peekc(L);
            if (c == '#') {
                size_t line = L->line, col = L->col;
                adv(L);
                uint64_t id;
                if ((st = instance_id(L, &id)) != GEOM_OK)
                    return st;
                if ((st = instance(L, id, line, col, 0)) != GEOM_OK)
                    return st;
            } else if (at(L, "ENDSEC")) {
                break;
            } else if (c < 0) {
                return err(L, GEOM_ERR_PARSE, "unexpected end of input in the DATA section (missing ENDSEC)%s", NULL);
            } else {
                return err(L, GEOM_ERR_PARSE, "expected an instance '#n = ...' or ENDSEC%s", NULL);
            }
        }
        if ((st = section_kw(L, "ENDSEC")) != GEOM_OK)
            return st;
        if ((st = expect(L, ';', "';' after ENDSEC")) != GEOM_OK)
            return st;
    }
    if (ndata == 0)
        return err(L, GEOM_ERR_PARSE, "no DATA section%s", NULL);
    if ((st = section_kw(L, "END-ISO-10303-21")) != GEOM_OK)
        return st;
    if ((st = expect(L, ';', "';' after END-ISO-10303-21")) != GEOM_OK)
        return st;
    return build_hash(L);
}

geom_status geom__p21_parse(geom__p21 *p, const char *text, size_t size, const char *source,
                            size_t max_bytes, int max_depth, const geom_allocator *alloc,
                            geom_diag *diag)
{
    memset(p, 0, sizeof *p);
    p->alloc = alloc;
    snprintf(p->source, sizeof p->source, "%s", source ? source : "<memory>");
    lexer L;
    memset(&L, 0, sizeof L);
    L.s = text;
    L.n = size;
    L.line = 1;
    L.col = 1;
    L.p = p;
    L.diag = diag;
    L.max_depth = max_depth > 0 ? max_depth : 64;
    if (size > (max_bytes ? max_bytes : ((size_t)1 << 30)))
        return geom__diag_set(diag, GEOM_ERR_LIMIT, p->source, 0, 0,
                             "input of %zu bytes exceeds the limit", size);
    /* Part 21 is 7-bit text: name UTF-16 and NUL bytes as such (issue 15) */
    if (size >= 2 && ((unsigned char)text[0] == 0xFF || (unsigned char)text[0] == 0xFE) &&
        ((unsigned char)text[1] == 0xFF || (unsigned char)text[1] == 0xFE) && text[0] != text[1])
        return geom__diag_set(diag, GEOM_ERR_PARSE, p->source, 1, 1,
                              "UTF-16 text: a STEP file is 7-bit ISO 10303-21 text");
    const char *nul = size ? memchr(text, '\0', size) : NULL;
    if (nul) {
        size_t line = 1, col = 1;
        for (const char *q = text; q < nul; q++) {
            if (*q == '\n')
                line++, col = 1;
            else
                col++;
        }
        return geom__diag_set(diag, GEOM_ERR_PARSE, p->source, line, col,
                              "NUL byte at byte offset %zu", (size_t)(nul - text));
    }
    geom_status st = parse_all(&L);
    if (st != GEOM_OK && diag && diag->status != st)
        geom__diag_set(diag, st, p->source, L.line, L.col, "%s", geom_status_str(st));
    geom__free(alloc, L.tmp, L.captmp * sizeof *L.tmp);
    if (st != GEOM_OK)
        geom__p21_free(p);
    return st;
}

void geom__p21_free(geom__p21 *p)
{
    const geom_allocator *a = p->alloc;
    geom__free(a, p->vals, p->capvals * sizeof *p->vals);
    geom__free(a, p->parts, p->capparts * sizeof *p->parts);
    geom__free(a, p->ents, p->capents * sizeof *p->ents);
    geom__free(a, p->pool, p->cappool);
    geom__hindex_free(&p->hash, a);
    memset(p, 0, sizeof *p);
    p->alloc = a;
}

const geom__p21_part_t *geom__p21_part(const geom__p21 *p, uint32_t e, const char *name)
{
    if (e >= p->nents)
        return NULL;
    const geom__p21_entity *E = &p->ents[e];
    for (uint32_t k = 0; k < E->nparts; k++) {
        const geom__p21_part_t *q = &p->parts[E->first_part + k];
        if (strcmp(p->pool + q->name, name) == 0)
            return q;
    }
    return NULL;
}

const char *geom__p21_type(const geom__p21 *p, uint32_t e)
{
    if (e >= p->nents)
        return "";
    return p->pool + p->parts[p->ents[e].first_part].name;
}
