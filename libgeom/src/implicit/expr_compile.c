/*
 * The expression compiler: a recursive-descent parser (recursion bounded by
 * the nesting depth limit) that emits a postfix program directly, with
 * peephole constant folding and integer-power detection. See implicit.h for
 * the language.
 */
#include "implicit/implicit_internal.h"

#include <float.h>
#include <limits.h>
#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------ op arities */

/* The named primitives, which evaluate at the point (x, y, z). */
static int op_is_primitive(int op)
{
    switch ((expr_op)op) {
    case OP_SPHERE1: case OP_SPHERE4: case OP_ELLIPSOID3: case OP_ELLIPSOID6:
    case OP_TORUS2: case OP_TORUS5: case OP_BOX3: case OP_BOX6: case OP_CYLINDER2:
    case OP_CYLINDER5: case OP_PLANE4: case OP_CAPSULE7: case OP_GYROID0: case OP_GYROID1:
    case OP_GYROID2:
        return 1;
    default:
        return 0;
    }
}

int geom__implicit_op_arity(int op)
{
    switch ((expr_op)op) {
    case OP_CONST: case OP_X: case OP_Y: case OP_Z: case OP_T: case OP_GYROID0:
        return 0;
    case OP_NEG: case OP_POWI: case OP_SQRT: case OP_ABS: case OP_SIN: case OP_COS:
    case OP_TAN: case OP_EXP: case OP_LOG: case OP_SPHERE1: case OP_GYROID1:
        return 1;
    case OP_ADD: case OP_SUB: case OP_MUL: case OP_DIV: case OP_POW: case OP_MIN:
    case OP_MAX: case OP_ATAN2: case OP_TORUS2: case OP_CYLINDER2: case OP_GYROID2:
        return 2;
    case OP_CLAMP: case OP_SMIN: case OP_SMAX: case OP_ELLIPSOID3: case OP_BOX3:
        return 3;
    case OP_SPHERE4: case OP_PLANE4:
        return 4;
    case OP_TORUS5: case OP_CYLINDER5:
        return 5;
    case OP_ELLIPSOID6: case OP_BOX6:
        return 6;
    case OP_CAPSULE7:
        return 7;
    case OP_COUNT:
        break;
    }
    return 0;
}

/* Pure operations of their arguments (foldable when these are constants). */
static int op_is_pure(int op)
{
    return op >= OP_ADD && op <= OP_SMAX;
}

/* --------------------------------------------------------------- functions */

enum {
    FN_FIXED = 0, /* ops[k] for k arguments, OP_COUNT where not allowed */
    FN_NARY = 1   /* two or more, folded with a binary op */
};

typedef struct fn_def {
    const char *name;
    int kind;
    int ops[8];     /* FN_FIXED: opcode by argument count (OP_COUNT = invalid) */
    int nary_op;    /* FN_NARY: the binary op */
    int negate_rest; /* FN_NARY: negate arguments 2.. (difference) */
    const char *counts; /* for messages: "1", "1 or 4", ... */
} fn_def;

#define NO OP_COUNT
static const fn_def fns[] = {
    {"sqrt", FN_FIXED, {NO, OP_SQRT, NO, NO, NO, NO, NO, NO}, 0, 0, "1"},
    {"abs", FN_FIXED, {NO, OP_ABS, NO, NO, NO, NO, NO, NO}, 0, 0, "1"},
    {"sin", FN_FIXED, {NO, OP_SIN, NO, NO, NO, NO, NO, NO}, 0, 0, "1"},
    {"cos", FN_FIXED, {NO, OP_COS, NO, NO, NO, NO, NO, NO}, 0, 0, "1"},
    {"tan", FN_FIXED, {NO, OP_TAN, NO, NO, NO, NO, NO, NO}, 0, 0, "1"},
    {"exp", FN_FIXED, {NO, OP_EXP, NO, NO, NO, NO, NO, NO}, 0, 0, "1"},
    {"log", FN_FIXED, {NO, OP_LOG, NO, NO, NO, NO, NO, NO}, 0, 0, "1"},
    {"pow", FN_FIXED, {NO, NO, OP_POW, NO, NO, NO, NO, NO}, 0, 0, "2"},
    {"atan2", FN_FIXED, {NO, NO, OP_ATAN2, NO, NO, NO, NO, NO}, 0, 0, "2"},
    {"clamp", FN_FIXED, {NO, NO, NO, OP_CLAMP, NO, NO, NO, NO}, 0, 0, "3"},
    {"min", FN_NARY, {0}, OP_MIN, 0, "at least 2"},
    {"max", FN_NARY, {0}, OP_MAX, 0, "at least 2"},
    {"union", FN_NARY, {0}, OP_MIN, 0, "at least 2"},
    {"intersection", FN_NARY, {0}, OP_MAX, 0, "at least 2"},
    {"difference", FN_NARY, {0}, OP_MAX, 1, "at least 2"},
    {"smooth_union", FN_FIXED, {NO, NO, NO, OP_SMIN, NO, NO, NO, NO}, 0, 0, "3"},
    {"smooth_intersection", FN_FIXED, {NO, NO, NO, OP_SMAX, NO, NO, NO, NO}, 0, 0, "3"},
    /* smooth_difference(a, b, k) = -smin(-a, b, k): emitted specially */
    {"smooth_difference", FN_FIXED, {NO, NO, NO, OP_SMIN, NO, NO, NO, NO}, 0, 0, "3"},
    {"sphere", FN_FIXED, {NO, OP_SPHERE1, NO, NO, OP_SPHERE4, NO, NO, NO}, 0, 0, "1 or 4"},
    {"ellipsoid", FN_FIXED, {NO, NO, NO, OP_ELLIPSOID3, NO, NO, OP_ELLIPSOID6, NO}, 0, 0,
     "3 or 6"},
    {"torus", FN_FIXED, {NO, NO, OP_TORUS2, NO, NO, OP_TORUS5, NO, NO}, 0, 0, "2 or 5"},
    {"box", FN_FIXED, {NO, NO, NO, OP_BOX3, NO, NO, OP_BOX6, NO}, 0, 0, "3 or 6"},
    {"cylinder", FN_FIXED, {NO, NO, OP_CYLINDER2, NO, NO, OP_CYLINDER5, NO, NO}, 0, 0,
     "2 or 5"},
    {"plane", FN_FIXED, {NO, NO, NO, NO, OP_PLANE4, NO, NO, NO}, 0, 0, "4"},
    {"capsule", FN_FIXED, {NO, NO, NO, NO, NO, NO, NO, OP_CAPSULE7}, 0, 0, "7"},
    {"gyroid", FN_FIXED, {OP_GYROID0, OP_GYROID1, OP_GYROID2, NO, NO, NO, NO, NO}, 0, 0,
     "0, 1 or 2"},
};
#undef NO

/* ------------------------------------------------------------------ lexer */

enum {
    TOK_END = 0,
    TOK_NUM,
    TOK_NAME,
    TOK_PUNCT /* one of + - * / ^ ( ) , */
};

typedef struct parser {
    const char *s;
    size_t len;
    size_t pos; /* next byte to lex */
    /* the current token */
    int tok;
    char punct;
    size_t tpos, tlen;
    double tval;

    size_t depth, max_depth;
    expr_ins *code;
    size_t n, cap;
    size_t sp, max_sp;
    unsigned vars;
    const geom_allocator *alloc;
    geom_diag *diag;
    geom_status err;
} parser;

/* Line and column (1-based) of byte offset off. */
static void locate(const parser *P, size_t off, size_t *line, size_t *col)
{
    size_t l = 1, start = 0;
    for (size_t i = 0; i < off && i < P->len; i++)
        if (P->s[i] == '\n') {
            l++;
            start = i + 1;
        }
    *line = l;
    *col = off - start + 1;
}

static void fail_at(parser *P, geom_status st, size_t off, const char *fmt, ...)
    GEOM_PRINTF(4, 5);
static void fail_at(parser *P, geom_status st, size_t off, const char *fmt, ...)
{
    if (P->err != GEOM_OK)
        return;
    P->err = st;
    if (!P->diag)
        return;
    char msg[GEOM_DIAG_MESSAGE_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    size_t line, col;
    locate(P, off, &line, &col);
    geom__diag_set(P->diag, st, "expression", line, col, "%s", msg);
}

/* A printable description of the current token for messages. */
static void describe(const parser *P, char *buf, size_t size)
{
    switch (P->tok) {
    case TOK_END:
        snprintf(buf, size, "end of input");
        break;
    case TOK_NUM:
        snprintf(buf, size, "number '%.*s'", (int)(P->tlen > 40 ? 40 : P->tlen), P->s + P->tpos);
        break;
    case TOK_NAME:
        snprintf(buf, size, "'%.*s'", (int)(P->tlen > 40 ? 40 : P->tlen), P->s + P->tpos);
        break;
    default:
        snprintf(buf, size, "'%c'", P->punct);
        break;
    }
}

static int is_alpha(int c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
static int is_digit(int c) { return c >= '0' && c <= '9'; }

/* strtod on a NUL-terminated copy, C-locale spelling ('.' as the decimal
 * point) whatever the current locale. Returns 0 on success. */
static int convert_number(const char *tok, size_t n, double *out)
{
    char buf[416];
    if (n >= sizeof buf)
        return -1;
    memcpy(buf, tok, n);
    buf[n] = '\0';
    char *end;
    double v = strtod(buf, &end);
    if ((size_t)(end - buf) != n) {
        const struct lconv *lc = localeconv();
        char *dot = strchr(buf, '.');
        if (!dot || !lc || !lc->decimal_point || strlen(lc->decimal_point) != 1)
            return -1;
        *dot = lc->decimal_point[0];
        v = strtod(buf, &end);
        if ((size_t)(end - buf) != n)
            return -1;
    }
    *out = v;
    return 0;
}

static void next(parser *P)
{
    if (P->err)
        return;
    while (P->pos < P->len) {
        char c = P->s[P->pos];
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f')
            P->pos++;
        else
            break;
    }
    P->tpos = P->pos;
    P->tlen = 0;
    if (P->pos >= P->len) {
        P->tok = TOK_END;
        return;
    }
    const char *s = P->s;
    size_t i = P->pos;
    unsigned char c = (unsigned char)s[i];
    if (is_digit(c) || (c == '.' && i + 1 < P->len && is_digit((unsigned char)s[i + 1]))) {
        size_t j = i;
        while (j < P->len && is_digit((unsigned char)s[j]))
            j++;
        if (j < P->len && s[j] == '.') {
            j++;
            while (j < P->len && is_digit((unsigned char)s[j]))
                j++;
        }
        if (j < P->len && (s[j] == 'e' || s[j] == 'E')) {
            size_t k = j + 1;
            if (k < P->len && (s[k] == '+' || s[k] == '-'))
                k++;
            if (k >= P->len || !is_digit((unsigned char)s[k])) {
                fail_at(P, GEOM_ERR_PARSE, i,
                        "malformed number '%.*s': expected digits in the exponent",
                        (int)((k - i) > 40 ? 40 : (k - i)), s + i);
                return;
            }
            while (k < P->len && is_digit((unsigned char)s[k]))
                k++;
            j = k;
        }
        if (j < P->len && (is_alpha((unsigned char)s[j]) || s[j] == '.')) {
            fail_at(P, GEOM_ERR_PARSE, j, "malformed number: unexpected '%c' after '%.*s'", s[j],
                    (int)((j - i) > 40 ? 40 : (j - i)), s + i);
            return;
        }
        double v;
        if (convert_number(s + i, j - i, &v) != 0) {
            fail_at(P, j - i >= 400 ? GEOM_ERR_LIMIT : GEOM_ERR_PARSE, i,
                    j - i >= 400 ? "number longer than 400 characters"
                                 : "malformed number '%.*s'",
                    (int)((j - i) > 40 ? 40 : (j - i)), s + i);
            return;
        }
        if (isinf(v)) {
            fail_at(P, GEOM_ERR_PARSE, i, "number '%.*s' is too large for a double",
                    (int)((j - i) > 40 ? 40 : (j - i)), s + i);
            return;
        }
        P->tok = TOK_NUM;
        P->tval = v;
        P->tlen = j - i;
        P->pos = j;
        return;
    }
    if (is_alpha(c)) {
        size_t j = i;
        while (j < P->len && (is_alpha((unsigned char)s[j]) || is_digit((unsigned char)s[j])))
            j++;
        P->tok = TOK_NAME;
        P->tlen = j - i;
        P->pos = j;
        return;
    }
    if (strchr("+-*/^(),", c) && c != '\0') {
        P->tok = TOK_PUNCT;
        P->punct = (char)c;
        P->tlen = 1;
        P->pos = i + 1;
        return;
    }
    if (c == '\0')
        fail_at(P, GEOM_ERR_PARSE, i, "unexpected NUL byte");
    else if (c >= 0x20 && c < 0x7f)
        fail_at(P, GEOM_ERR_PARSE, i, "unexpected character '%c'", c);
    else
        fail_at(P, GEOM_ERR_PARSE, i, "unexpected byte 0x%02x", c);
}

static int is_punct(const parser *P, char c)
{
    return P->err == GEOM_OK && P->tok == TOK_PUNCT && P->punct == c;
}

static int tok_is(const parser *P, const char *name)
{
    size_t n = strlen(name);
    return P->tok == TOK_NAME && P->tlen == n && memcmp(P->s + P->tpos, name, n) == 0;
}

/* --------------------------------------------------------------- emitter */

static void emit(parser *P, int op, int n, double c, size_t at)
{
    if (P->err)
        return;
    int k = geom__implicit_op_arity(op);
    /* x ^ integer constant: an exact integer power. */
    if (op == OP_POW && P->n >= 1 && P->code[P->n - 1].op == OP_CONST &&
        !(P->n >= 2 && P->code[P->n - 2].op == OP_CONST)) {
        double e = P->code[P->n - 1].c;
        if (e == nearbyint(e) && fabs(e) <= 1073741824.0) {
            P->n--;
            P->sp--;
            op = OP_POWI;
            n = (int)e;
            k = 1;
        }
    }
    /* Fold pure operations of constants. */
    if (op_is_pure(op) || op == OP_POWI) {
        int all = (size_t)k <= P->n;
        for (int i = 1; all && i <= k; i++)
            all = P->code[P->n - (size_t)i].op == OP_CONST;
        if (all && k > 0) {
            expr_ins tmp[8];
            for (int i = 0; i < k; i++)
                tmp[i] = P->code[P->n - (size_t)k + (size_t)i];
            tmp[k].op = op;
            tmp[k].n = n;
            tmp[k].c = c;
            double v = geom__implicit_run_double(tmp, (size_t)k + 1, 0.0, 0.0, 0.0, 0.0);
            P->n -= (size_t)k;
            P->sp -= (size_t)k;
            op = OP_CONST;
            n = 0;
            c = v;
            k = 0;
        }
    }
    void *code = P->code;
    geom_status gst = geom__grow(P->alloc, &code, &P->cap, P->n + 1, sizeof(expr_ins));
    if (gst != GEOM_OK) {
        fail_at(P, gst, at, gst == GEOM_ERR_LIMIT ? "program too large" : "out of memory");
        return;
    }
    P->code = code;
    P->code[P->n].op = op;
    P->code[P->n].n = n;
    P->code[P->n].c = c;
    P->n++;
    P->sp = P->sp - (size_t)k + 1;
    if (P->sp > P->max_sp)
        P->max_sp = P->sp;
    if (P->max_sp > GEOM_IMPLICIT_STACK_MAX)
        fail_at(P, GEOM_ERR_LIMIT, at,
                "expression needs more than %d evaluation stack slots", GEOM_IMPLICIT_STACK_MAX);
}

/* ----------------------------------------------------------------- parser */

static void parse_expr(parser *P);
static void parse_unary(parser *P);

static void expect_operand_error(parser *P)
{
    char what[64];
    describe(P, what, sizeof what);
    fail_at(P, GEOM_ERR_PARSE, P->tpos, "expected a number, a name or '(', found %s", what);
}

/* After an argument of fn's list (opened at open_pos), neither ',' nor ')':
 * the parse error, unless one is already set. */
static void expected_comma_or_paren(parser *P, const fn_def *fn, size_t open_pos)
{
    if (P->err)
        return;
    char what[64];
    describe(P, what, sizeof what);
    size_t ol, oc;
    locate(P, open_pos, &ol, &oc);
    fail_at(P, GEOM_ERR_PARSE, P->tpos,
            "expected ',' or ')' in the arguments of '%s' (opened at column %zu), found %s",
            fn->name, oc, what);
}

static void parse_call(parser *P, const fn_def *fn, size_t name_pos)
{
    size_t open_pos = P->tpos;
    next(P); /* '(' */
    int count = 0;
    if (is_punct(P, ')')) {
        next(P);
    } else {
        for (;;) {
            if (P->err)
                return;
            size_t arg_pos = P->tpos;
            parse_expr(P);
            if (P->err)
                return;
            count++;
            if (fn->kind == FN_NARY && count >= 2) {
                if (fn->negate_rest)
                    emit(P, OP_NEG, 0, 0.0, arg_pos);
                emit(P, fn->nary_op, 0, 0.0, name_pos);
            } else if (fn->kind == FN_FIXED && count > 7) {
                fail_at(P, GEOM_ERR_PARSE, name_pos, "'%s' takes %s arguments, got more than 7",
                        fn->name, fn->counts);
                return;
            }
            if (is_punct(P, ',')) {
                next(P);
                continue;
            }
            if (is_punct(P, ')')) {
                next(P);
                break;
            }
            expected_comma_or_paren(P, fn, open_pos);
            return;
        }
    }
    if (fn->kind == FN_NARY) {
        if (count < 2)
            fail_at(P, GEOM_ERR_PARSE, name_pos, "'%s' takes %s arguments, got %d", fn->name,
                    fn->counts, count);
        return;
    }
    int op = fn->ops[count];
    if (op == OP_COUNT) {
        fail_at(P, GEOM_ERR_PARSE, name_pos, "'%s' takes %s argument%s, got %d", fn->name,
                fn->counts, strcmp(fn->counts, "1") == 0 ? "" : "s", count);
        return;
    }
    if (op_is_primitive(op)) /* primitives read the point itself */
        P->vars |= GEOM_IMPLICIT_VAR_X | GEOM_IMPLICIT_VAR_Y | GEOM_IMPLICIT_VAR_Z;
    emit(P, op, 0, 0.0, name_pos);
}

static void parse_primary(parser *P)
{
    if (P->err)
        return;
    if (P->tok == TOK_NUM) {
        emit(P, OP_CONST, 0, P->tval, P->tpos);
        next(P);
        return;
    }
    if (is_punct(P, '(')) {
        size_t open_pos = P->tpos;
        next(P);
        parse_expr(P);
        if (P->err)
            return;
        if (!is_punct(P, ')')) {
            char what[64];
            describe(P, what, sizeof what);
            size_t ol, oc;
            locate(P, open_pos, &ol, &oc);
            fail_at(P, GEOM_ERR_PARSE, P->tpos, "expected ')' to close '(' at column %zu, found %s",
                    oc, what);
            return;
        }
        next(P);
        return;
    }
    if (P->tok != TOK_NAME) {
        expect_operand_error(P);
        return;
    }
    size_t name_pos = P->tpos, name_len = P->tlen;
    const char *name = P->s + P->tpos;
    int shown = (int)(name_len > 40 ? 40 : name_len);
    static const struct {
        const char *name;
        int op;
        unsigned var;
        double c;
    } atoms[] = {{"x", OP_X, GEOM_IMPLICIT_VAR_X, 0.0}, {"y", OP_Y, GEOM_IMPLICIT_VAR_Y, 0.0},
                 {"z", OP_Z, GEOM_IMPLICIT_VAR_Z, 0.0}, {"t", OP_T, GEOM_IMPLICIT_VAR_T, 0.0},
                 {"pi", OP_CONST, 0, GEOM_PI},          {"e", OP_CONST, 0, 2.71828182845904523536}};
    for (size_t i = 0; i < sizeof atoms / sizeof atoms[0]; i++) {
        if (tok_is(P, atoms[i].name)) {
            next(P);
            if (is_punct(P, '(')) {
                fail_at(P, GEOM_ERR_PARSE, name_pos, "'%.*s' is not a function", shown, name);
                return;
            }
            P->vars |= atoms[i].var;
            emit(P, atoms[i].op, 0, atoms[i].c, name_pos);
            return;
        }
    }
    const fn_def *fn = NULL;
    for (size_t i = 0; i < sizeof fns / sizeof fns[0]; i++)
        if (tok_is(P, fns[i].name)) {
            fn = &fns[i];
            break;
        }
    next(P);
    if (P->err)
        return;
    if (!fn) {
        if (is_punct(P, '('))
            fail_at(P, GEOM_ERR_PARSE, name_pos, "unknown function '%.*s'", shown, name);
        else
            fail_at(P, GEOM_ERR_PARSE, name_pos,
                    "unknown identifier '%.*s' (variables are x, y, z, t; constants pi, e)",
                    shown, name);
        return;
    }
    if (!is_punct(P, '(')) {
        char what[64];
        describe(P, what, sizeof what);
        fail_at(P, GEOM_ERR_PARSE, P->tpos, "expected '(' after the function '%s', found %s",
                fn->name, what);
        return;
    }
    if (strcmp(fn->name, "smooth_difference") == 0) {
        /* smooth_difference(a, b, k) = -smin(-a, b, k) = smax(a, -b, k):
         * emit a, then -b, then k, then SMAX. */
        size_t open_pos = P->tpos;
        next(P);
        int count = 0;
        while (!P->err) {
            if (count == 0 && is_punct(P, ')'))
                break;
            parse_expr(P);
            if (P->err)
                return;
            count++;
            if (count == 2)
                emit(P, OP_NEG, 0, 0.0, name_pos);
            if (is_punct(P, ',')) {
                next(P);
                continue;
            }
            if (is_punct(P, ')'))
                break;
            expected_comma_or_paren(P, fn, open_pos);
            return;
        }
        if (P->err)
            return;
        next(P); /* ')' */
        if (count != 3) {
            fail_at(P, GEOM_ERR_PARSE, name_pos, "'%s' takes 3 arguments, got %d", fn->name,
                    count);
            return;
        }
        emit(P, OP_SMAX, 0, 0.0, name_pos);
        return;
    }
    parse_call(P, fn, name_pos);
}

/* power := primary ('^' unary)? */
static void parse_power(parser *P)
{
    parse_primary(P);
    if (P->err)
        return;
    if (is_punct(P, '^')) {
        size_t at = P->tpos;
        next(P);
        parse_unary(P);
        emit(P, OP_POW, 0, 0.0, at);
    }
}

/* unary := ('-' | '+') unary | power; the nesting depth is counted here,
 * which every recursive path of the parser goes through. */
static void parse_unary(parser *P)
{
    if (P->err)
        return;
    if (++P->depth > P->max_depth) {
        fail_at(P, GEOM_ERR_LIMIT, P->tpos, "expression nested deeper than %zu levels",
                P->max_depth);
        P->depth--;
        return;
    }
    if (is_punct(P, '-') || is_punct(P, '+')) {
        int neg = P->punct == '-';
        size_t at = P->tpos;
        next(P);
        parse_unary(P);
        if (neg)
            emit(P, OP_NEG, 0, 0.0, at);
    } else {
        parse_power(P);
    }
    P->depth--;
}

/* term := unary (('*' | '/') unary)* */
static void parse_term(parser *P)
{
    parse_unary(P);
    while (!P->err && (is_punct(P, '*') || is_punct(P, '/'))) {
        int op = P->punct == '*' ? OP_MUL : OP_DIV;
        size_t at = P->tpos;
        next(P);
        parse_unary(P);
        emit(P, op, 0, 0.0, at);
    }
}

/* expr := term (('+' | '-') term)* */
static void parse_expr(parser *P)
{
    parse_term(P);
    while (!P->err && (is_punct(P, '+') || is_punct(P, '-'))) {
        int op = P->punct == '+' ? OP_ADD : OP_SUB;
        size_t at = P->tpos;
        next(P);
        parse_term(P);
        emit(P, op, 0, 0.0, at);
    }
}

/* ----------------------------------------------------------------- public */

geom_status geom_implicit_expr_compile(const char *text, size_t len,
                                       const geom_implicit_expr_options *opt,
                                       geom_implicit_expr **out, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (!text && len > 0))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "expression", 0, 0,
                             "NULL text or output");
    parser P;
    memset(&P, 0, sizeof P);
    P.s = text ? text : "";
    P.len = len;
    P.alloc = opt ? opt->alloc : NULL;
    P.diag = diag;
    P.max_depth = opt && opt->max_depth ? opt->max_depth : GEOM_IMPLICIT_DEPTH_DEFAULT;
    if (P.max_depth > GEOM_IMPLICIT_DEPTH_MAX)
        P.max_depth = GEOM_IMPLICIT_DEPTH_MAX;
    size_t max_len = opt && opt->max_length ? opt->max_length : GEOM_IMPLICIT_LENGTH_DEFAULT;
    if (len > max_len) {
        fail_at(&P, GEOM_ERR_LIMIT, max_len, "expression longer than %zu bytes", max_len);
        return P.err;
    }
    next(&P);
    if (!P.err)
        parse_expr(&P);
    if (!P.err && P.tok != TOK_END) {
        char what[64];
        describe(&P, what, sizeof what);
        if (P.tok == TOK_PUNCT && P.punct == ')')
            fail_at(&P, GEOM_ERR_PARSE, P.tpos, "unmatched ')'");
        else
            fail_at(&P, GEOM_ERR_PARSE, P.tpos, "expected an operator or end of input, found %s",
                    what);
    }
    if (!P.err && (P.n == 0 || P.sp != 1))
        fail_at(&P, GEOM_ERR_PARSE, 0, "internal error: malformed program");
    if (P.err) {
        geom__free(P.alloc, P.code, P.cap * sizeof(expr_ins));
        return P.err;
    }
    geom_implicit_expr *e = geom__alloc(P.alloc, sizeof *e);
    if (!e) {
        geom__free(P.alloc, P.code, P.cap * sizeof(expr_ins));
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "expression", 0, 0, "out of memory");
    }
    memset(e, 0, sizeof *e);
    e->code = P.code;
    e->n = P.n;
    e->cap = P.cap;
    e->max_stack = P.max_sp;
    e->vars = P.vars;
    e->t = 0.0;
    if (P.alloc)
        e->alloc = *P.alloc;
    *out = e;
    return GEOM_OK;
}

void geom_implicit_expr_destroy(geom_implicit_expr *e)
{
    if (!e)
        return;
    geom_allocator a = e->alloc;
    geom__free(&a, e->code, e->cap * sizeof(expr_ins));
    geom__free(&a, e, sizeof *e);
}

void geom_implicit_expr_set_time(geom_implicit_expr *e, double t)
{
    if (e)
        e->t = t;
}

size_t geom_implicit_expr_size(const geom_implicit_expr *e)
{
    return e ? e->n : 0;
}

unsigned geom_implicit_expr_variables(const geom_implicit_expr *e)
{
    return e ? e->vars : 0u;
}
