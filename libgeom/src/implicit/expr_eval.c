/*
 * Evaluation of compiled expressions: values (double), exact gradients
 * (forward-mode dual numbers with three derivative components) and interval
 * bounds (outward-rounded interval arithmetic), all from one interpreter
 * written over a numeric type (expr_template.h).
 */
#include "implicit/implicit_internal.h"

#include <float.h>
#include <math.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/* ================================================================ doubles */

/* NaN-propagating min and max (ties: the first argument). */
static inline double d_min(double a, double b)
{
    if (isnan(a) || isnan(b))
        return NAN;
    return a <= b ? a : b;
}
static inline double d_max(double a, double b)
{
    if (isnan(a) || isnan(b))
        return NAN;
    return a >= b ? a : b;
}
static inline double d_cst(double c) { return c; }
static inline double d_add(double a, double b) { return a + b; }
static inline double d_sub(double a, double b) { return a - b; }
static inline double d_mul(double a, double b) { return a * b; }
static inline double d_div(double a, double b) { return a / b; }
static inline double d_neg(double a) { return -a; }
static inline double d_sqr(double a) { return a * a; }
/* Powers with NaN propagation (C's pow(1, NaN) and pow(NaN, 0) are 1). */
static inline double d_powi(double a, int n)
{
    if (isnan(a))
        return a;
    if (n == 2)
        return a * a;
    return pow(a, (double)n);
}
static inline double d_pow(double a, double b)
{
    if (isnan(a) || isnan(b))
        return NAN;
    /* a negative base needs an integer exponent, -inf included (C's
     * pow(-inf, 0.5) is +inf) */
    if (a < 0.0 && b != nearbyint(b))
        return NAN;
    return pow(a, b);
}
static inline double d_sqrt(double a) { return sqrt(a); }
static inline double d_abs(double a) { return fabs(a); }
static inline double d_sin(double a) { return sin(a); }
static inline double d_cos(double a) { return cos(a); }
static inline double d_tan(double a) { return tan(a); }
static inline double d_exp(double a) { return exp(a); }
static inline double d_log(double a) { return log(a); }
static inline double d_atan2(double a, double b) { return atan2(a, b); }

#define NUM double
#define F(name) d_##name
#include "implicit/expr_template.h"
#undef NUM
#undef F

/* Batch evaluation (expr_batch_template.h): LANES points at a time. */
enum { LANES = 32, BATCH_STACK = 64 };

#define NUM double
#define F(name) d_##name
#define BATCH_LANES LANES
#include "implicit/expr_batch_template.h"
#undef BATCH_LANES
#undef NUM
#undef F

static void d_run_batch(const expr_ins *code, size_t ncode, size_t n, const double *p, double t,
                        double *out)
{
    double X[LANES], Y[LANES], Z[LANES];
    for (size_t base = 0; base < n; base += LANES) {
        size_t L = n - base < LANES ? n - base : LANES;
        const double *P = p + 3 * base;
        for (size_t l = 0; l < L; l++) {
            X[l] = P[3 * l];
            Y[l] = P[3 * l + 1];
            Z[l] = P[3 * l + 2];
        }
        d_run_lanes(code, ncode, L, X, Y, Z, t, out + base);
    }
}

/* Blocks of XB points with operands in place: each stack slot is a vector
 * of XB lanes or one constant (a push of x, y or z points at the gathered
 * coordinates, a constant or t stays a scalar until an operation needs
 * lanes), and each operation writes a slot buffer different from its
 * operands, so its lane loop is a plain vectorisable loop over restrict
 * arrays (AVX2/AVX-512 clones). An operation on constants only is done
 * once on the scalars: the same d_* function, the same value. Every lane
 * does exactly d_run's operations, so the results are bitwise d_run's. */
/* XPLAN: the steps of a plan on the stack (longer programs allocate it);
 * XSTREAM: from this many points (4 MiB of values) on, the values are
 * written with non-temporal stores (measured: 0.8 instead of 1.3 ms for
 * 10^6 distances into a new numpy array). */
enum { XB = 64, XSTACK = 24, XPLAN = 48, XKC = 8, XSTREAM = 1 << 19 };

/* The lane loop of a binary operation for each operand kind. */
#define XB_BINARY(FN)                                                                          \
    do {                                                                                       \
        if (va && vb)                                                                          \
            for (int l = 0; l < XB; l++)                                                       \
                r[l] = FN(va[l], vb[l]);                                                       \
        else if (va)                                                                           \
            for (int l = 0; l < XB; l++)                                                       \
                r[l] = FN(va[l], cb);                                                          \
        else                                                                                   \
            for (int l = 0; l < XB; l++)                                                       \
                r[l] = FN(ca, vb[l]);                                                          \
    } while (0)

GEOM__CLONE_INLINE void x_binary(int op, double *restrict r, const double *restrict va, double ca,
                                 const double *restrict vb, double cb)
{
    switch (op) {
    case OP_ADD: XB_BINARY(d_add); break;
    case OP_SUB: XB_BINARY(d_sub); break;
    case OP_MUL: XB_BINARY(d_mul); break;
    case OP_DIV: XB_BINARY(d_div); break;
    case OP_POW: XB_BINARY(d_pow); break;
    case OP_MIN: XB_BINARY(d_min); break;
    case OP_MAX: XB_BINARY(d_max); break;
    default: XB_BINARY(d_atan2); break; /* OP_ATAN2 */
    }
}
#undef XB_BINARY

static double d_scalar_binary(int op, double a, double b)
{
    switch (op) {
    case OP_ADD: return d_add(a, b);
    case OP_SUB: return d_sub(a, b);
    case OP_MUL: return d_mul(a, b);
    case OP_DIV: return d_div(a, b);
    case OP_POW: return d_pow(a, b);
    case OP_MIN: return d_min(a, b);
    case OP_MAX: return d_max(a, b);
    default: return d_atan2(a, b);
    }
}

#define XB_UNARY(FN)                                                                           \
    for (int l = 0; l < XB; l++)                                                               \
    r[l] = FN(va[l])

GEOM__CLONE_INLINE void x_unary(const expr_ins *in, double *restrict r, const double *restrict va)
{
    switch ((expr_op)in->op) {
    case OP_NEG: XB_UNARY(d_neg); break;
    case OP_SQRT: XB_UNARY(d_sqrt); break;
    case OP_ABS: XB_UNARY(d_abs); break;
    case OP_SIN: XB_UNARY(d_sin); break;
    case OP_COS: XB_UNARY(d_cos); break;
    case OP_TAN: XB_UNARY(d_tan); break;
    case OP_EXP: XB_UNARY(d_exp); break;
    case OP_LOG: XB_UNARY(d_log); break;
    default: /* OP_POWI */
        if (in->n == 2) { /* powi(a, 2) without its branches, as d_run_lanes */
            XB_UNARY(d_sqr);
        } else {
            for (int l = 0; l < XB; l++)
                r[l] = d_powi(va[l], in->n);
        }
        break;
    }
}
#undef XB_UNARY

static double d_scalar_unary(const expr_ins *in, double a)
{
    switch ((expr_op)in->op) {
    case OP_NEG: return d_neg(a);
    case OP_SQRT: return d_sqrt(a);
    case OP_ABS: return d_abs(a);
    case OP_SIN: return d_sin(a);
    case OP_COS: return d_cos(a);
    case OP_TAN: return d_tan(a);
    case OP_EXP: return d_exp(a);
    case OP_LOG: return d_log(a);
    default: return d_powi(a, in->n);
    }
}

#define XB_LANES(EXPR)                                                                         \
    for (int l = 0; l < XB; l++)                                                               \
    r[l] = (EXPR)

/* The pair "a*b then add or subtract it from the slot below" (sums of
 * products) in one lane loop, rounding each operation as the two would. */
GEOM__CLONE_INLINE void x_mul_addsub(int sub, double *restrict r, const double *restrict lf,
                                     const double *restrict va, double ca,
                                     const double *restrict vb, double cb)
{
    if (va && vb) {
        if (sub)
            XB_LANES(d_sub(lf[l], d_mul(va[l], vb[l])));
        else
            XB_LANES(d_add(lf[l], d_mul(va[l], vb[l])));
    } else if (va) {
        if (sub)
            XB_LANES(d_sub(lf[l], d_mul(va[l], cb)));
        else
            XB_LANES(d_add(lf[l], d_mul(va[l], cb)));
    } else {
        if (sub)
            XB_LANES(d_sub(lf[l], d_mul(ca, vb[l])));
        else
            XB_LANES(d_add(lf[l], d_mul(ca, vb[l])));
    }
}

/* sqrt or abs, then +, -, *, / a constant (distances: sqrt(...) - r,
 * abs(x) - h) in one lane loop. */
#define XB_UNARY_CONST(U)                                                                      \
    do {                                                                                       \
        if (bop == OP_ADD)                                                                     \
            XB_LANES(d_add(U(va[l]), c));                                                      \
        else if (bop == OP_SUB)                                                                \
            XB_LANES(d_sub(U(va[l]), c));                                                      \
        else if (bop == OP_MUL)                                                                \
            XB_LANES(d_mul(U(va[l]), c));                                                      \
        else                                                                                   \
            XB_LANES(d_div(U(va[l]), c));                                                      \
    } while (0)

GEOM__CLONE_INLINE void x_unary_const(int uop, int bop, double *restrict r,
                                      const double *restrict va, double c)
{
    if (uop == OP_SQRT)
        XB_UNARY_CONST(d_sqrt);
    else
        XB_UNARY_CONST(d_abs);
}

/* x_unary_const with r its own operand. */
GEOM__CLONE_INLINE void x_unary_const_inplace(int uop, int bop, double *r, double c)
{
    const double *va = r;
    if (uop == OP_SQRT)
        XB_UNARY_CONST(d_sqrt);
    else
        XB_UNARY_CONST(d_abs);
}
#undef XB_UNARY_CONST
#undef XB_LANES

static int is_addsub(int op) { return op == OP_ADD || op == OP_SUB; }
static int is_arith(int op) { return is_addsub(op) || op == OP_MUL || op == OP_DIV; }

/* The block evaluator runs a plan: which slots hold lanes and which hold
 * constants, which buffer each operation writes, which pairs fuse and
 * every operation on constants only do not depend on the points, so they
 * are worked out once per call (x_plan) and each block of XB points only
 * gathers its coordinates and runs the plan's lane loops. */
enum {
    XK_BINARY,     /* r = op(a, b) */
    XK_MULADDSUB,  /* r = f +- a*b (op2: 1 for -) */
    XK_UNARY,      /* r = op(a) */
    XK_UNARY_CONST, /* r = op(a) op2 cb, op sqrt or abs */
    XK_FILL,       /* r = ca in every lane */
    XK_LANEWISE,   /* clamp, smin, smax or a primitive, lane by lane */
    XK_ROW_PRIM,   /* a grid row's primitive of constant arguments a (y ca, z cb) */
    XK_DOT         /* r = ((args0 args1) +- args2 args3) [+- args4 args5], then
                      optionally r = op(r) op2 cb (sqrt or abs, then + - * /) */
};
typedef struct xstep {
    int kind, op, op2, k;
    const expr_ins *in;
    double *r;
    const double *va, *vb, *vf;
    double ca, cb;
    const double *args[8];
    double a[8]; /* XK_ROW_PRIM: the constant arguments */
    int sub[2];  /* XK_DOT: the second and third terms are subtracted */
    /* a row plan's constants of the row (x_rec): ca, cb and a[q] are u[t -
     * 1] of the row when the tag t is not 0 */
    int ta, tb, at[8];
} xstep;

/* A constant worked out from the row's y and z (x_plan with a record): u[0]
 * is y, u[1] z, u[2 + i] the tape's step i, an operation on earlier u or
 * literal constants, redone for every row. */
typedef struct xtape {
    int kind; /* 1, 2 or 3 operands: d_scalar_unary, d_scalar_binary, x_fold3 */
    int op;
    const expr_ins *in;
    int t[3];    /* operand tags (u index + 1), 0: the literal c */
    double c[3];
} xtape;
/* What a row plan redoes for each row: the tape, and where its values go
 * besides the steps' tags. */
typedef struct xrec {
    xtape *tape;
    size_t ntape;
    int kc_tag[XKC]; /* w->kc rows filled with a constant of the row */
    size_t nkc;
    int fill_yz;     /* w->Y, w->Z hold y and z (a lane-by-lane primitive) */
    int res_tag;
} xrec;

/* The tag of an operation's folded result (0 when every operand is a
 * literal constant): the operation goes on rec's tape. */
static int x_tape(xrec *rec, int kind, int op, const expr_ins *in, const int *tg,
                  const double *c)
{
    if (!rec || !(tg[0] || (kind > 1 && tg[1]) || (kind > 2 && tg[2])))
        return 0;
    xtape *t = &rec->tape[rec->ntape];
    t->kind = kind;
    t->op = op;
    t->in = in;
    for (int q = 0; q < kind; q++) {
        t->t[q] = tg[q];
        t->c[q] = c[q];
    }
    return (int)(2 + rec->ntape++) + 1;
}

/* clamp, smin or smax of constants. */
static double x_fold3(int op, double a0, double a1, double a2)
{
    return op == OP_CLAMP  ? d_clamp(a0, a1, a2)
           : op == OP_SMIN ? d_smin(a0, a1, a2)
                           : d_neg(d_smin(d_neg(a0), d_neg(a1), a2));
}

/* The lanes of one block: coordinates and two buffers per stack slot. */
typedef struct xwork {
    _Alignas(64) double X[XB]; /* whole cache lines for every vector */
    double Y[XB], Z[XB];
    double buf[XSTACK][2][XB];
    double kc[XKC][XB]; /* constants as lanes, for the operands of XK_DOT */
} xwork;

/* The plan of the program over w's buffers into plan (ncode steps at
 * most): the number of steps; *res gets the result's lanes, or NULL and
 * *res_c its constant value. The program's max_stack must be at most
 * XSTACK. yz NULL: blocks of points (x, y, z in w's X, Y, Z); else the
 * nodes of a grid row (x in w->X, y = yz[0] and z = yz[1] constants), where
 * an operation on y, z and constants alone is done once on the scalars and
 * a primitive of constant arguments is one XK_ROW_PRIM step (row_prim). */
static size_t x_plan(const expr_ins *code, size_t ncode, double t, const double *yz, xwork *w,
                     xstep *plan, const double **res, double *res_c, xrec *rec)
{
    const double *v[XSTACK]; /* lanes of a slot, NULL: the constant c[slot] */
    double c[XSTACK];
    int tg[XSTACK]; /* the constant's tag (rec) */
    size_t sp = 0, ns = 0;
    v[0] = NULL;
    c[0] = NAN;
    tg[0] = 0;
    /* The buffer an operation writes into slot q: not the slot's operand. */
#define DST(q) w->buf[q][v[q] == w->buf[q][0]]
    for (size_t i = 0; i < ncode; i++) {
        const expr_ins *in = &code[i];
        xstep *s = &plan[ns];
        int op = in->op;
        s->ta = s->tb = 0;
        if (op == OP_POWI && in->n == 2 && v[sp - 1] && sp < XSTACK) {
            /* a^2 on lanes is a*a (d_powi's value but for the NaN it passes
             * on, a NaN either way): the product of the slot and a copy, so
             * that it fuses into sums of squares like x*x */
            v[sp] = v[sp - 1];
            c[sp] = c[sp - 1];
            sp++;
            op = OP_MUL;
        }
        switch ((expr_op)op) {
        case OP_CONST: v[sp] = NULL; tg[sp] = 0; c[sp++] = in->c; break;
        case OP_T: v[sp] = NULL; tg[sp] = 0; c[sp++] = t; break;
        case OP_X: v[sp++] = w->X; break;
        case OP_Y:
            v[sp] = yz ? NULL : w->Y;
            tg[sp] = 1;
            c[sp++] = yz ? yz[0] : NAN;
            break;
        case OP_Z:
            v[sp] = yz ? NULL : w->Z;
            tg[sp] = 2;
            c[sp++] = yz ? yz[1] : NAN;
            break;
        case OP_ADD: case OP_SUB: case OP_MUL: case OP_DIV: case OP_POW: case OP_MIN:
        case OP_MAX: case OP_ATAN2: {
            size_t a = sp - 2, b = sp - 1;
            if (!v[a] && !v[b]) {
                tg[a] = x_tape(rec, 2, op, in, &tg[a], &c[a]);
                c[a] = d_scalar_binary(op, c[a], c[b]);
                sp--;
                break;
            }
            s->va = v[a], s->ca = c[a], s->vb = v[b], s->cb = c[b];
            s->ta = v[a] ? 0 : tg[a], s->tb = v[b] ? 0 : tg[b];
            if (op == OP_MUL && i + 1 < ncode && is_addsub(code[i + 1].op) && sp >= 3 &&
                v[sp - 3]) {
                size_t f = sp - 3; /* fused with the next add/sub */
                i++;
                s->kind = XK_MULADDSUB;
                s->op2 = code[i].op == OP_SUB;
                s->vf = v[f];
                s->r = DST(f);
                v[f] = s->r;
                sp--;
            } else {
                s->kind = XK_BINARY;
                s->op = op;
                s->r = DST(a);
                v[a] = s->r;
            }
            ns++;
            sp--;
            break;
        }
        case OP_NEG: case OP_SQRT: case OP_ABS: case OP_SIN: case OP_COS: case OP_TAN:
        case OP_EXP: case OP_LOG: case OP_POWI: {
            size_t a = sp - 1;
            if (!v[a]) {
                tg[a] = x_tape(rec, 1, op, in, &tg[a], &c[a]);
                c[a] = d_scalar_unary(in, c[a]);
                break;
            }
            s->va = v[a];
            s->op = in->op;
            s->in = in;
            if ((in->op == OP_SQRT || in->op == OP_ABS) && i + 2 < ncode &&
                code[i + 1].op == OP_CONST && is_arith(code[i + 2].op)) {
                i += 2; /* fused with "constant, operation" */
                s->kind = XK_UNARY_CONST;
                s->op2 = code[i].op;
                s->cb = code[i - 1].c;
            } else {
                s->kind = XK_UNARY;
            }
            s->r = DST(a);
            v[a] = s->r;
            ns++;
            break;
        }
        case OP_COUNT:
            break;
        default: { /* clamp, smin, smax and the primitives, lane by lane */
            size_t k = (size_t)geom__implicit_op_arity(in->op);
            size_t first = sp - k;
            int lanes = 0;
            for (size_t q = first; q < sp; q++)
                lanes |= v[q] != NULL;
            if (!lanes && k > 0 &&
                (in->op == OP_CLAMP || in->op == OP_SMIN || in->op == OP_SMAX)) {
                tg[first] = x_tape(rec, 3, in->op, in, &tg[first], &c[first]);
                c[first] = x_fold3(in->op, c[first], c[first + 1], c[first + 2]);
                sp = first + 1;
                break;
            }
            if (yz && !lanes) {
                s->kind = XK_ROW_PRIM;
                s->op = in->op;
                s->k = (int)k;
                for (size_t q = 0; q < k; q++) {
                    s->a[q] = c[first + q];
                    s->at[q] = tg[first + q];
                }
                s->ca = yz[0];
                s->cb = yz[1];
                s->ta = 1;
                s->tb = 2;
                s->r = k == 0 ? w->buf[first][1] : DST(first);
                v[first] = s->r;
                ns++;
                sp = first + 1;
                break;
            }
            if (yz && in->op != OP_CLAMP && in->op != OP_SMIN && in->op != OP_SMAX) {
                for (int l = 0; l < XB; l++) { /* the primitive reads y and z lanes */
                    w->Y[l] = yz[0];
                    w->Z[l] = yz[1];
                }
                if (rec)
                    rec->fill_yz = 1;
            }
            if (!yz && in->op == OP_SPHERE1 && !v[first]) {
                /* sphere(r): sqrt((x*x + y*y) + z*z) - r, d_len3's operations */
                memset(s, 0, sizeof *s);
                s->kind = XK_DOT;
                s->k = 3;
                s->args[0] = s->args[1] = w->X;
                s->args[2] = s->args[3] = w->Y;
                s->args[4] = s->args[5] = w->Z;
                s->op = OP_SQRT;
                s->op2 = OP_SUB;
                s->cb = c[first];
                s->r = DST(first);
                v[first] = s->r;
                ns++;
                break;
            }
            for (size_t q = first; q < sp; q++)
                if (!v[q]) {
                    s->kind = XK_FILL;
                    s->r = w->buf[q][0];
                    s->ca = c[q];
                    s->ta = tg[q];
                    v[q] = s->r;
                    s = &plan[++ns];
                    s->ta = s->tb = 0;
                }
            s->kind = XK_LANEWISE;
            s->op = in->op;
            s->k = (int)k;
            for (size_t q = 0; q < k; q++)
                s->args[q] = v[first + q];
            s->r = k == 0 ? w->buf[first][1] : DST(first);
            v[first] = s->r;
            ns++;
            sp = first + 1;
            break;
        }
        }
    }
#undef DST
    *res = v[0];
    *res_c = c[0];
    if (rec)
        rec->res_tag = v[0] ? 0 : tg[0];
    return ns;
}

/* The lanes of operand v (NULL: the constant c) for XK_DOT: v, or a row of
 * w->kc filled with c (*nk rows used); NULL when the rows are used up. */
static const double *x_lanes(xwork *w, size_t *nk, const double *v, double c, int tag,
                             xrec *rec)
{
    if (v)
        return v;
    if (*nk == XKC)
        return NULL;
    if (rec)
        rec->kc_tag[*nk] = tag;
    double *r = w->kc[(*nk)++];
    for (int l = 0; l < XB; l++)
        r[l] = c;
    return r;
}

/* Sums of two or three products (a product, then one or two fused
 * multiply-add/subtract steps each adding to the previous result: dot
 * products, sums of squares), with a following "sqrt or abs, then a
 * constant operation" step on the sum, become one XK_DOT step: one lane
 * loop with the same operations in the same order. Returns the new number
 * of steps. */
static size_t x_fuse(xstep *plan, size_t ns, xwork *w, xrec *rec)
{
    size_t nk = 0, m = 0;
    for (size_t j = 0; j < ns; j++) {
        xstep *s = &plan[j];
        size_t terms = 1;
        while (terms < 3 && j + terms < ns && plan[j + terms].kind == XK_MULADDSUB &&
               plan[j + terms].vf == plan[j + terms - 1].r)
            terms++;
        if (s->kind != XK_BINARY || s->op != OP_MUL || terms < 2) {
            plan[m++] = *s;
            continue;
        }
        xstep d;
        memset(&d, 0, sizeof d);
        d.kind = XK_DOT;
        d.k = (int)terms;
        size_t nk0 = nk;
        int ok = 1;
        for (size_t q = 0; q < terms; q++) {
            const xstep *t = &plan[j + q];
            d.args[2 * q] = x_lanes(w, &nk, t->va, t->ca, t->ta, rec);
            d.args[2 * q + 1] = x_lanes(w, &nk, t->vb, t->cb, t->tb, rec);
            ok = ok && d.args[2 * q] && d.args[2 * q + 1];
            if (q > 0)
                d.sub[q - 1] = t->op2;
        }
        if (!ok) {
            nk = nk0;
            plan[m++] = *s;
            continue;
        }
        d.r = plan[j + terms - 1].r;
        j += terms - 1;
        if (j + 1 < ns && plan[j + 1].kind == XK_UNARY_CONST && plan[j + 1].va == d.r) {
            j++;
            d.op = plan[j].op;
            d.op2 = plan[j].op2;
            d.cb = plan[j].cb;
            d.r = plan[j].r;
        }
        plan[m++] = d;
    }
    if (rec)
        rec->nkc = nk;
    return m;
}

/* A lane-by-lane step (clamp, smin, smax, a primitive) over one block. */
static void x_lanewise(const xstep *s, double *r, const xwork *w)
{
    for (int l = 0; l < XB; l++) {
        double args[8];
        for (int q = 0; q < s->k; q++)
            args[q] = s->args[q][l];
        if (s->op == OP_CLAMP)
            r[l] = d_clamp(args[0], args[1], args[2]);
        else if (s->op == OP_SMIN)
            r[l] = d_smin(args[0], args[1], args[2]);
        else if (s->op == OP_SMAX)
            r[l] = d_neg(d_smin(d_neg(args[0]), d_neg(args[1]), args[2]));
        else
            r[l] = d_prim(s->op, w->X[l], w->Y[l], w->Z[l], s->k ? args : NULL);
    }
}

#define XB_LANES(EXPR)                                                                         \
    for (int l = 0; l < XB; l++)                                                               \
    r[l] = (EXPR)
/* An XK_DOT step into r. */
GEOM__CLONE_INLINE void x_dot(const xstep *s, double *restrict r)
{
    const double *restrict a = s->args[0], *restrict b = s->args[1];
    const double *restrict c = s->args[2], *restrict d = s->args[3];
    if (s->k == 2) {
        if (s->sub[0])
            XB_LANES(d_sub(d_mul(a[l], b[l]), d_mul(c[l], d[l])));
        else
            XB_LANES(d_add(d_mul(a[l], b[l]), d_mul(c[l], d[l])));
    } else {
        const double *restrict e = s->args[4], *restrict f = s->args[5];
        switch (s->sub[0] * 2 + s->sub[1]) {
        case 0: XB_LANES(d_add(d_add(d_mul(a[l], b[l]), d_mul(c[l], d[l])), d_mul(e[l], f[l]))); break;
        case 1: XB_LANES(d_sub(d_add(d_mul(a[l], b[l]), d_mul(c[l], d[l])), d_mul(e[l], f[l]))); break;
        case 2: XB_LANES(d_add(d_sub(d_mul(a[l], b[l]), d_mul(c[l], d[l])), d_mul(e[l], f[l]))); break;
        default: XB_LANES(d_sub(d_sub(d_mul(a[l], b[l]), d_mul(c[l], d[l])), d_mul(e[l], f[l]))); break;
        }
    }
    if (s->op)
        x_unary_const_inplace(s->op, s->op2, r, s->cb);
}
#undef XB_LANES

/* XB values r into out: plainly, or (nt) with non-temporal stores, which
 * write whole lines without reading them first and leave the caches to the
 * rest (out 16-byte aligned). */
GEOM__CLONE_INLINE void x_store(double *restrict out, const double *restrict r, int nt)
{
#if defined(__SSE2__)
    if (nt) {
        for (int l = 0; l < XB; l += 2)
            _mm_stream_pd(out + l, _mm_load_pd(r + l));
        return;
    }
#else
    (void)nt;
#endif
    memcpy(out, r, XB * sizeof(double));
}

GEOM__CLONE_INLINE void x_store_done(int nt)
{
#if defined(__SSE2__)
    if (nt)
        _mm_sfence();
#else
    (void)nt;
#endif
}

/* The distance-like programs U((x*x + y*y) + z*z) B c (U sqrt or abs, B one
 * of + - * /, or none: uop 0), sphere(c) among them, straight from the
 * points: nb blocks of XB points p into out (nt: as x_store), no lanes in
 * between. Each point gets x_dot's operations in x_dot's order. */
#define XL_LOOP(EXPR)                                                                          \
    for (int l = 0; l < XB; l++) {                                                             \
        double x = p[3 * l], y = p[3 * l + 1], z = p[3 * l + 2];                               \
        double s = d_add(d_add(d_mul(x, x), d_mul(y, y)), d_mul(z, z));                        \
        r[l] = (EXPR);                                                                         \
    }
#define XL_TAIL(U)                                                                             \
    do {                                                                                       \
        if (bop == OP_ADD)                                                                     \
            XL_LOOP(d_add(U(s), c))                                                            \
        else if (bop == OP_SUB)                                                                \
            XL_LOOP(d_sub(U(s), c))                                                            \
        else if (bop == OP_MUL)                                                                \
            XL_LOOP(d_mul(U(s), c))                                                            \
        else                                                                                   \
            XL_LOOP(d_div(U(s), c))                                                            \
    } while (0)
GEOM_SIMD_CLONES
static void d_run_len(int uop, int bop, double c, size_t nb, const double *restrict p,
                      double *restrict out, int nt)
{
    _Alignas(64) double tmp[XB];
    for (size_t blk = 0; blk < nb; blk++, p += 3 * XB, out += XB) {
        double *restrict r = nt ? tmp : out;
        if (uop == OP_SQRT)
            XL_TAIL(d_sqrt);
        else if (uop == OP_ABS)
            XL_TAIL(d_abs);
        else
            XL_LOOP(s)
        if (nt)
            x_store(out, tmp, 1);
    }
    x_store_done(nt);
}
#undef XL_TAIL
#undef XL_LOOP

/* Is the plan (ns steps over w) one step U((x*x + y*y) + z*z) [B c]? */
static int x_is_len(const xstep *plan, size_t ns, const xwork *w)
{
    const xstep *s = plan;
    return ns == 1 && s->kind == XK_DOT && s->k == 3 && !s->sub[0] && !s->sub[1] &&
           s->args[0] == w->X && s->args[1] == w->X && s->args[2] == w->Y &&
           s->args[3] == w->Y && s->args[4] == w->Z && s->args[5] == w->Z;
}

/* The coordinates of XB points p (3 doubles each) into X, Y and Z. */
GEOM__CLONE_INLINE void x_gather(double *restrict X, double *restrict Y, double *restrict Z,
                                 const double *restrict p)
{
    for (int l = 0; l < XB; l++) {
        X[l] = p[3 * l];
        Y[l] = p[3 * l + 1];
        Z[l] = p[3 * l + 2];
    }
}

#define ROW_LANES(EXPR)                                                                        \
    for (int l = 0; l < XB; l++)                                                               \
    r[l] = (EXPR)

/* r[l] = d_prim(op, x[l], y, z, a) for XB lanes, a the constant arguments. */
GEOM__CLONE_INLINE void row_prim(int op, double *restrict r, const double *restrict x, double y,
                                 double z, const double *a)
{
    switch ((expr_op)op) {
    case OP_SPHERE1: ROW_LANES(d_sub(d_len3(x[l], y, z), a[0])); break;
    case OP_SPHERE4: {
        double qy = d_sub(y, a[1]), qz = d_sub(z, a[2]);
        ROW_LANES(d_sub(d_len3(d_sub(x[l], a[0]), qy, qz), a[3]));
        break;
    }
    case OP_ELLIPSOID3: ROW_LANES(d_ellipsoid(x[l], y, z, a[0], a[1], a[2])); break;
    case OP_ELLIPSOID6: {
        double qy = d_sub(y, a[1]), qz = d_sub(z, a[2]);
        ROW_LANES(d_ellipsoid(d_sub(x[l], a[0]), qy, qz, a[3], a[4], a[5]));
        break;
    }
    case OP_TORUS2: ROW_LANES(d_torus(x[l], y, z, a[0], a[1])); break;
    case OP_TORUS5: {
        double qy = d_sub(y, a[1]), qz = d_sub(z, a[2]);
        ROW_LANES(d_torus(d_sub(x[l], a[0]), qy, qz, a[3], a[4]));
        break;
    }
    case OP_BOX3: ROW_LANES(d_box(x[l], y, z, a[0], a[1], a[2])); break;
    case OP_BOX6: {
        double qy = d_sub(y, a[1]), qz = d_sub(z, a[2]);
        ROW_LANES(d_box(d_sub(x[l], a[0]), qy, qz, a[3], a[4], a[5]));
        break;
    }
    case OP_CYLINDER2: ROW_LANES(d_cylinder(x[l], y, z, a[0], a[1])); break;
    case OP_CYLINDER5: {
        double qy = d_sub(y, a[1]), qz = d_sub(z, a[2]);
        ROW_LANES(d_cylinder(d_sub(x[l], a[0]), qy, qz, a[3], a[4]));
        break;
    }
    case OP_PLANE4: ROW_LANES(d_plane(x[l], y, z, a[0], a[1], a[2], a[3])); break;
    default: ROW_LANES(d_prim(op, x[l], y, z, a)); break; /* capsule, gyroids */
    }
}
#undef ROW_LANES

/* Blocks of XB points into out (nt: as x_store) through the plan (ns
 * steps over w, result res or the constant res_c). row 0: n points p (3
 * doubles each), XB divides n; row 1: the n >= XB nodes (p[b], y, z) of a
 * grid row (the plan's, x_plan with yz), where the last block overlaps
 * the one before when XB does not divide n (its lanes are recomputed, to
 * the same values). Without nt, the last step writes its lanes into out
 * directly when they are the result. */
GEOM_SIMD_CLONES
static void d_run_blocks(const xstep *plan, size_t ns, xwork *w, const double *res, double res_c,
                         size_t n, const double *p, int row, double *out, int nt)
{
    size_t last = ns > 0 && plan[ns - 1].r == res && !nt ? ns - 1 : ns;
    for (size_t b0 = 0; b0 < n; b0 += XB) {
        if (b0 + XB > n)
            b0 = n - XB;
        double *o = out + b0;
        if (row)
            memcpy(w->X, p + b0, sizeof w->X);
        else
            x_gather(w->X, w->Y, w->Z, p + 3 * b0);
        for (size_t j = 0; j < ns; j++) {
            const xstep *s = &plan[j];
            double *r = j == last ? o : s->r;
            switch (s->kind) {
            case XK_BINARY: x_binary(s->op, r, s->va, s->ca, s->vb, s->cb); break;
            case XK_MULADDSUB: x_mul_addsub(s->op2, r, s->vf, s->va, s->ca, s->vb, s->cb); break;
            case XK_UNARY: x_unary(s->in, r, s->va); break;
            case XK_UNARY_CONST: x_unary_const(s->op, s->op2, r, s->va, s->cb); break;
            case XK_FILL:
                for (int l = 0; l < XB; l++)
                    r[l] = s->ca;
                break;
            case XK_DOT: x_dot(s, r); break;
            case XK_ROW_PRIM: row_prim(s->op, r, w->X, s->ca, s->cb, s->k ? s->a : NULL); break;
            default: x_lanewise(s, r, w); break;
            }
        }
        if (last < ns)
            continue;
        if (res) {
            x_store(o, res, nt);
        } else {
            for (int l = 0; l < XB; l++)
                o[l] = res_c;
        }
    }
    x_store_done(nt);
}

/* The program of e over n >= XB points p (3 doubles each, XB divides n)
 * into out (nt: as x_store), through a plan made for this call.
 * e->max_stack <= XSTACK. Returns 0 (out untouched) when a long program's
 * plan cannot be allocated. */
static int x_run(const geom_implicit_expr *e, size_t n, const double *p, double *out, int nt)
{
    xwork w;
    xstep small[XPLAN];
    xstep *plan = e->n <= XPLAN ? small : geom__alloc(&e->alloc, e->n * sizeof *plan);
    if (!plan)
        return 0;
    const double *res;
    double res_c;
    size_t ns = x_plan(e->code, e->n, e->t, NULL, &w, plan, &res, &res_c, NULL);
    ns = x_fuse(plan, ns, &w, NULL);
    if (x_is_len(plan, ns, &w) && res == plan[0].r)
        d_run_len(plan[0].op, plan[0].op2, plan[0].cb, n / XB, p, out, nt);
    else
        d_run_blocks(plan, ns, &w, res, res_c, n, p, 0, out, nt);
    if (plan != small)
        geom__free(&e->alloc, plan, e->n * sizeof *plan);
    return 1;
}

/* ================================================================== duals */

typedef struct dual {
    double v;
    double d[3];
} dual;

/* f'(x) * dx where a zero dx absorbs an infinite or NaN f'(x). */
GEOM__CLONE_INLINE double chain(double fp, double dx)
{
    /* the product, its bits cleared (+0) where dx is zero: a select the
     * compiler vectorises, not a branch */
    double m = fp * dx;
    uint64_t b;
    memcpy(&b, &m, sizeof b);
    b &= (uint64_t)0 - (uint64_t)(dx != 0.0);
    memcpy(&m, &b, sizeof m);
    return m;
}

GEOM__CLONE_INLINE dual g_cst(double c)
{
    dual r = {c, {0.0, 0.0, 0.0}};
    return r;
}
GEOM__CLONE_INLINE dual g_unary(double v, double fp, dual a)
{
    dual r;
    r.v = v;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
        r.d[i] = chain(fp, a.d[i]);
    return r;
}
GEOM__CLONE_INLINE dual g_add(dual a, dual b)
{
    dual r;
    r.v = a.v + b.v;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
        r.d[i] = a.d[i] + b.d[i];
    return r;
}
GEOM__CLONE_INLINE dual g_sub(dual a, dual b)
{
    dual r;
    r.v = a.v - b.v;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
        r.d[i] = a.d[i] - b.d[i];
    return r;
}
GEOM__CLONE_INLINE dual g_mul(dual a, dual b)
{
    dual r;
    r.v = a.v * b.v;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
        r.d[i] = chain(b.v, a.d[i]) + chain(a.v, b.d[i]);
    return r;
}
GEOM__CLONE_INLINE dual g_div(dual a, dual b)
{
    dual r;
    r.v = a.v / b.v;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
        r.d[i] = chain(1.0 / b.v, a.d[i]) - chain(r.v / b.v, b.d[i]);
    return r;
}
GEOM__CLONE_INLINE dual g_neg(dual a)
{
    dual r;
    r.v = -a.v;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
        r.d[i] = -a.d[i];
    return r;
}
GEOM__CLONE_INLINE dual g_sqr(dual a) { return g_unary(a.v * a.v, 2.0 * a.v, a); }
GEOM__CLONE_INLINE dual g_powi(dual a, int n)
{
    if (n == 0)
        return g_cst(d_powi(a.v, 0));
    double fp = (double)n * (n == 2 ? a.v : pow(a.v, (double)(n - 1)));
    return g_unary(d_powi(a.v, n), fp, a);
}
GEOM__CLONE_INLINE dual g_pow(dual a, dual b)
{
    dual r;
    r.v = d_pow(a.v, b.v);
    double fa = b.v * pow(a.v, b.v - 1.0);
    double fb = r.v * log(a.v);
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
        r.d[i] = chain(fa, a.d[i]) + chain(fb, b.d[i]);
    return r;
}
GEOM__CLONE_INLINE dual g_sqrt(dual a)
{
    double v = sqrt(a.v);
    return g_unary(v, 0.5 / v, a);
}
GEOM__CLONE_INLINE dual g_abs(dual a)
{
    double s = a.v > 0.0 ? 1.0 : a.v < 0.0 ? -1.0 : a.v == 0.0 ? 0.0 : NAN;
    return g_unary(fabs(a.v), s, a);
}
GEOM__CLONE_INLINE dual g_sin(dual a) { return g_unary(sin(a.v), cos(a.v), a); }
GEOM__CLONE_INLINE dual g_cos(dual a) { return g_unary(cos(a.v), -sin(a.v), a); }
GEOM__CLONE_INLINE dual g_tan(dual a)
{
    double v = tan(a.v);
    return g_unary(v, 1.0 + v * v, a);
}
GEOM__CLONE_INLINE dual g_exp(dual a)
{
    double v = exp(a.v);
    return g_unary(v, v, a);
}
GEOM__CLONE_INLINE dual g_log(dual a) { return g_unary(log(a.v), 1.0 / a.v, a); }
GEOM__CLONE_INLINE dual g_nan(void)
{
    dual r = {NAN, {NAN, NAN, NAN}};
    return r;
}
GEOM__CLONE_INLINE dual g_min(dual a, dual b)
{
    if (isnan(a.v) || isnan(b.v))
        return g_nan();
    return a.v <= b.v ? a : b;
}
GEOM__CLONE_INLINE dual g_max(dual a, dual b)
{
    if (isnan(a.v) || isnan(b.v))
        return g_nan();
    return a.v >= b.v ? a : b;
}
GEOM__CLONE_INLINE dual g_atan2(dual y, dual x)
{
    dual r;
    r.v = atan2(y.v, x.v);
    double r2 = x.v * x.v + y.v * y.v;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
        r.d[i] = r2 == 0.0 ? 0.0 : chain(x.v / r2, y.d[i]) - chain(y.v / r2, x.d[i]);
    return r;
}

#define NUM dual
#define F(name) g_##name
#include "implicit/expr_template.h"
#undef NUM
#undef F

/* ============================================================== intervals */

/* [lo, hi]; lo = hi = NaN is the empty interval (no defined value). */
typedef struct ival {
    double lo, hi;
} ival;

static inline ival iv_make(double lo, double hi)
{
    ival r = {lo, hi};
    return r;
}
static inline ival iv_empty(void) { return iv_make(NAN, NAN); }
static inline ival iv_whole(void) { return iv_make(-INFINITY, INFINITY); }
static inline int iv_isempty(ival a) { return isnan(a.lo) || isnan(a.hi); }
static inline double dn1(double x) { return nextafter(x, -INFINITY); }
static inline double up1(double x) { return nextafter(x, INFINITY); }
/* Margins for the C library's functions: 4 ulp relative (plus a few
 * subnormal steps), then one more step outward. */
static inline double dnm(double x)
{
    if (!isfinite(x))
        return x;
    return dn1(x - (fabs(x) * (4.0 * DBL_EPSILON) + 4.0 * DBL_TRUE_MIN));
}
static inline double upm(double x)
{
    if (!isfinite(x))
        return x;
    return up1(x + (fabs(x) * (4.0 * DBL_EPSILON) + 4.0 * DBL_TRUE_MIN));
}
/* Endpoints that came out NaN (inf - inf, inf / inf) mean "unbounded". */
static inline ival iv_fix(double lo, double hi)
{
    if (isnan(lo))
        lo = -INFINITY;
    if (isnan(hi))
        hi = INFINITY;
    return iv_make(lo, hi);
}
static inline double min2(double a, double b) { return a < b ? a : b; }
static inline double max2(double a, double b) { return a > b ? a : b; }

static inline ival i_cst(double c) { return iv_make(c, c); }
static inline ival i_add(ival a, ival b)
{
    if (iv_isempty(a) || iv_isempty(b))
        return iv_empty();
    return iv_fix(dn1(a.lo + b.lo), up1(a.hi + b.hi));
}
static inline ival i_sub(ival a, ival b)
{
    if (iv_isempty(a) || iv_isempty(b))
        return iv_empty();
    return iv_fix(dn1(a.lo - b.hi), up1(a.hi - b.lo));
}
static inline ival i_neg(ival a) { return iv_make(-a.hi, -a.lo); }
/* Product where 0 * inf = 0 (the set product over the reals). */
static inline double mul0(double a, double b)
{
    return (a == 0.0 || b == 0.0) ? 0.0 : a * b;
}
static inline ival i_mul(ival a, ival b)
{
    if (iv_isempty(a) || iv_isempty(b))
        return iv_empty();
    double p[4] = {mul0(a.lo, b.lo), mul0(a.lo, b.hi), mul0(a.hi, b.lo), mul0(a.hi, b.hi)};
    double lo = p[0], hi = p[0];
    for (int i = 1; i < 4; i++) {
        lo = min2(lo, p[i]);
        hi = max2(hi, p[i]);
    }
    return iv_fix(dn1(lo), up1(hi));
}
static inline ival i_div(ival a, ival b)
{
    if (iv_isempty(a) || iv_isempty(b))
        return iv_empty();
    if (b.lo <= 0.0 && b.hi >= 0.0)
        return iv_whole();
    double q[4] = {a.lo / b.lo, a.lo / b.hi, a.hi / b.lo, a.hi / b.hi};
    double lo = q[0], hi = q[0];
    for (int i = 0; i < 4; i++) {
        if (isnan(q[i]))
            return iv_whole();
        lo = min2(lo, q[i]);
        hi = max2(hi, q[i]);
    }
    return iv_fix(dn1(lo), up1(hi));
}
static inline ival i_sqr(ival a)
{
    if (iv_isempty(a))
        return a;
    double l2 = a.lo * a.lo, h2 = a.hi * a.hi;
    if (a.lo >= 0.0)
        return iv_make(max2(0.0, dn1(l2)), up1(h2));
    if (a.hi <= 0.0)
        return iv_make(max2(0.0, dn1(h2)), up1(l2));
    return iv_make(0.0, up1(max2(l2, h2)));
}
/* a^n, n >= 0 (pow from the C library, so the margins apply). */
static ival i_powi_pos(ival a, int n)
{
    if (n == 0)
        return iv_make(1.0, 1.0);
    if (n == 1)
        return a;
    if (n == 2)
        return i_sqr(a);
    double pl = pow(a.lo, (double)n), ph = pow(a.hi, (double)n);
    if (n % 2) /* odd: increasing */
        return iv_fix(dnm(pl), upm(ph));
    if (a.lo >= 0.0)
        return iv_fix(max2(0.0, dnm(pl)), upm(ph));
    if (a.hi <= 0.0)
        return iv_fix(max2(0.0, dnm(ph)), upm(pl));
    return iv_fix(0.0, upm(max2(pl, ph)));
}
static inline ival i_powi(ival a, int n)
{
    if (iv_isempty(a))
        return a;
    if (n >= 0)
        return i_powi_pos(a, n);
    /* n < 0: the point value is pow(a, n), 1 / a^|n| up to an ulp. */
    ival p = i_powi_pos(a, -n);
    ival r;
    if (p.lo > 0.0 || p.hi < 0.0) {
        r = iv_make(1.0 / p.hi, 1.0 / p.lo);
    } else if (p.lo >= 0.0) {
        r = iv_make(1.0 / p.hi, INFINITY);
    } else if (p.hi <= 0.0) {
        r = iv_make(-INFINITY, 1.0 / p.lo);
    } else {
        return iv_whole();
    }
    return iv_fix(dnm(r.lo), upm(r.hi));
}
static inline ival i_sqrt(ival a)
{
    if (iv_isempty(a) || a.hi < 0.0)
        return iv_empty();
    double lo = max2(a.lo, 0.0);
    return iv_make(max2(0.0, dn1(sqrt(lo))), up1(sqrt(a.hi)));
}
static inline ival i_log(ival a)
{
    if (iv_isempty(a) || a.hi < 0.0)
        return iv_empty();
    double lo = max2(a.lo, 0.0);
    return iv_make(dnm(log(lo)), upm(log(a.hi)));
}
static inline ival i_exp(ival a)
{
    if (iv_isempty(a))
        return a;
    return iv_make(max2(0.0, dnm(exp(a.lo))), upm(exp(a.hi)));
}
/* a ^ b over intervals: integer point exponents exactly, otherwise
 * exp(b log a) over the part of a where the power is defined. */
static ival i_pow(ival a, ival b)
{
    if (iv_isempty(a) || iv_isempty(b))
        return iv_empty();
    if (b.lo == b.hi && b.lo == nearbyint(b.lo) && fabs(b.lo) <= 1073741824.0) {
        /* The point value is the C library's pow: widen by its margin. */
        ival r = i_powi(a, (int)b.lo);
        return iv_isempty(r) ? r : iv_fix(dnm(r.lo), upm(r.hi));
    }
    if (a.lo < 0.0) {
        /* Negative bases are defined only for integer exponents. */
        int has_int = floor(b.hi) >= b.lo;
        if (has_int)
            return iv_whole();
        if (a.hi < 0.0)
            return iv_empty();
        a.lo = 0.0;
    }
    /* For a >= 0: a^b = exp(b log a), monotone in each argument. */
    ival l = i_log(a);
    ival e = i_mul(b, l);
    ival r = i_exp(e);
    /* pow(0, 0) = 1 and pow(0, b > 0) = 0 are limits the product covers;
     * make sure exact corner values are inside. */
    if (a.lo == 0.0) {
        if (b.lo <= 0.0 && b.hi >= 0.0) {
            r.lo = min2(r.lo, 0.0);
            r.hi = max2(r.hi, 1.0);
        }
        if (b.hi > 0.0)
            r.lo = min2(r.lo, 0.0);
        if (b.lo < 0.0)
            r.hi = INFINITY;
    }
    return r;
}
static inline ival i_abs(ival a)
{
    if (iv_isempty(a))
        return a;
    if (a.lo >= 0.0)
        return a;
    if (a.hi <= 0.0)
        return iv_make(-a.hi, -a.lo);
    return iv_make(0.0, max2(-a.lo, a.hi));
}
static inline ival i_min(ival a, ival b)
{
    if (iv_isempty(a) || iv_isempty(b))
        return iv_empty();
    return iv_make(min2(a.lo, b.lo), min2(a.hi, b.hi));
}
static inline ival i_max(ival a, ival b)
{
    if (iv_isempty(a) || iv_isempty(b))
        return iv_empty();
    return iv_make(max2(a.lo, b.lo), max2(a.hi, b.hi));
}

#define TWO_PI (2.0 * GEOM_PI)
/* Does [lo, hi] (possibly) contain phase + k*period for an integer k?
 * Errs on the side of yes. */
static int may_contain(double lo, double hi, double phase, double period)
{
    double k0 = ceil((lo - phase) / period - 1e-6);
    return k0 <= (hi - phase) / period + 1e-6;
}
/* sin or cos over a: endpoint values, plus the extremes +-1 where a may
 * contain a maximum (at pmax + 2k pi) or a minimum (at pmax + pi + 2k pi). */
static ival i_periodic(ival a, double (*fn)(double), double pmax)
{
    if (iv_isempty(a))
        return a;
    if (!isfinite(a.lo) || !isfinite(a.hi) || a.hi - a.lo >= TWO_PI || fabs(a.lo) > 1e8 ||
        fabs(a.hi) > 1e8)
        return iv_make(-1.0, 1.0);
    double s0 = fn(a.lo), s1 = fn(a.hi);
    double lo = max2(-1.0, dnm(min2(s0, s1))), hi = min2(1.0, upm(max2(s0, s1)));
    if (may_contain(a.lo, a.hi, pmax, TWO_PI))
        hi = 1.0;
    if (may_contain(a.lo, a.hi, pmax + GEOM_PI, TWO_PI))
        lo = -1.0;
    return iv_make(lo, hi);
}
static inline ival i_sin(ival a) { return i_periodic(a, sin, 0.5 * GEOM_PI); }
static inline ival i_cos(ival a) { return i_periodic(a, cos, 0.0); }
static inline ival i_tan(ival a)
{
    if (iv_isempty(a))
        return a;
    if (!isfinite(a.lo) || !isfinite(a.hi) || a.hi - a.lo >= GEOM_PI || fabs(a.lo) > 1e8 ||
        fabs(a.hi) > 1e8 || may_contain(a.lo, a.hi, 0.5 * GEOM_PI, GEOM_PI))
        return iv_whole();
    return iv_make(dnm(tan(a.lo)), upm(tan(a.hi)));
}
static inline ival i_atan2(ival y, ival x)
{
    if (iv_isempty(y) || iv_isempty(x))
        return iv_empty();
    double pi_up = up1(GEOM_PI);
    /* Around the origin, or across/along the branch cut (x < 0, y = 0). */
    if ((x.lo <= 0.0 && x.hi >= 0.0 && y.lo <= 0.0 && y.hi >= 0.0) ||
        (x.lo < 0.0 && y.lo <= 0.0 && y.hi >= 0.0))
        return iv_make(-pi_up, pi_up);
    /* Elsewhere atan2 is continuous on the box and its extremes are at the
     * corners (the angular extent of a convex set seen from outside). */
    double c[4] = {atan2(y.lo, x.lo), atan2(y.lo, x.hi), atan2(y.hi, x.lo), atan2(y.hi, x.hi)};
    double lo = c[0], hi = c[0];
    for (int i = 1; i < 4; i++) {
        lo = min2(lo, c[i]);
        hi = max2(hi, c[i]);
    }
    return iv_make(max2(-pi_up, dnm(lo)), min2(pi_up, upm(hi)));
}

#define NUM ival
#define F(name) i_##name
#include "implicit/expr_template.h"
#undef NUM
#undef F

/* ============================================ intervals with definedness */

/* An interval and a flag: nan = 1 when the point evaluation may give NaN
 * (or has no finite bound) somewhere in the box. NaN propagates through
 * every point operation, so the final value is NaN at a point exactly when
 * some operation made one there from non-NaN operands; with all operands
 * finite (every interval bounded) that happens only in sqrt and log of a
 * negative number and pow of a negative base with a non-integer exponent,
 * flagged here; any unbounded or empty interval is flagged too (inf - inf,
 * 0 * inf, 0 / 0 become possible). */
typedef struct ivn {
    ival v;
    int nan;
} ivn;

static inline ivn n_mk(ival v, int nan)
{
    ivn r;
    r.v = v;
    r.nan = nan || iv_isempty(v) || !isfinite(v.lo) || !isfinite(v.hi);
    return r;
}
static inline ivn n_cst(double c) { return n_mk(i_cst(c), 0); }
/* Sums and products of non-negative numbers are non-negative in floating
 * point too: the outward step below 0 is dropped (sqrt of a sum of squares
 * stays defined). */
static inline ival nonneg(ival r, ival a, ival b)
{
    if (a.lo >= 0.0 && b.lo >= 0.0 && r.lo < 0.0)
        r.lo = 0.0;
    return r;
}
static inline ivn n_add(ivn a, ivn b)
{
    return n_mk(nonneg(i_add(a.v, b.v), a.v, b.v), a.nan | b.nan);
}
static inline ivn n_sub(ivn a, ivn b) { return n_mk(i_sub(a.v, b.v), a.nan | b.nan); }
static inline ivn n_mul(ivn a, ivn b)
{
    return n_mk(nonneg(i_mul(a.v, b.v), a.v, b.v), a.nan | b.nan);
}
static inline ivn n_div(ivn a, ivn b) { return n_mk(i_div(a.v, b.v), a.nan | b.nan); }
static inline ivn n_neg(ivn a) { return n_mk(i_neg(a.v), a.nan); }
static inline ivn n_sqr(ivn a) { return n_mk(i_sqr(a.v), a.nan); }
static inline ivn n_powi(ivn a, int n) { return n_mk(i_powi(a.v, n), a.nan); }
static inline ivn n_pow(ivn a, ivn b)
{
    int intexp = b.v.lo == b.v.hi && b.v.lo == nearbyint(b.v.lo);
    return n_mk(i_pow(a.v, b.v), a.nan | b.nan | (a.v.lo < 0.0 && !intexp));
}
static inline ivn n_sqrt(ivn a) { return n_mk(i_sqrt(a.v), a.nan | (a.v.lo < 0.0)); }
static inline ivn n_log(ivn a) { return n_mk(i_log(a.v), a.nan | (a.v.lo < 0.0)); }
static inline ivn n_abs(ivn a) { return n_mk(i_abs(a.v), a.nan); }
static inline ivn n_sin(ivn a) { return n_mk(i_sin(a.v), a.nan); }
static inline ivn n_cos(ivn a) { return n_mk(i_cos(a.v), a.nan); }
static inline ivn n_tan(ivn a) { return n_mk(i_tan(a.v), a.nan); }
static inline ivn n_exp(ivn a) { return n_mk(i_exp(a.v), a.nan); }
static inline ivn n_min(ivn a, ivn b) { return n_mk(i_min(a.v, b.v), a.nan | b.nan); }
static inline ivn n_max(ivn a, ivn b) { return n_mk(i_max(a.v, b.v), a.nan | b.nan); }
static inline ivn n_atan2(ivn a, ivn b) { return n_mk(i_atan2(a.v, b.v), a.nan | b.nan); }

#define NUM ivn
#define F(name) n_##name
#include "implicit/expr_template.h"
#undef NUM
#undef F

/* ================================================================ public */

double geom__implicit_run_double(const expr_ins *code, size_t n, double x, double y, double z,
                            double t)
{
    return d_run(code, n, x, y, z, t);
}

double geom_implicit_expr_eval(const geom_implicit_expr *e, const double p[3])
{
    if (!e || !p)
        return NAN;
    return d_run(e->code, e->n, p[0], p[1], p[2], e->t);
}

void geom_implicit_expr_eval_many(const geom_implicit_expr *e, size_t n, const double *p,
                                  double *out)
{
    if (!out)
        return;
    if (!e || (!p && n > 0)) {
        for (size_t i = 0; i < n; i++)
            out[i] = NAN;
        return;
    }
    /* the blocks start at a 64-byte boundary of p when a few points (8 at
     * most: 8 points are 3 cache lines) go first */
    size_t head = 0;
    while (head < 8 && (uintptr_t)(p + 3 * head) % 64 != 0)
        head++;
    if (head == 8)
        head = 0;
    if (e->max_stack <= XSTACK && n >= head + XB) {
        size_t done = head + (n - head) / XB * XB;
        d_run_batch(e->code, e->n, head, p, e->t, out);
        int nt = n >= XSTREAM && (uintptr_t)(out + head) % 16 == 0;
        if (!x_run(e, done - head, p + 3 * head, out + head, nt))
            done = head;
        d_run_batch(e->code, e->n, n - done, p + 3 * done, e->t, out + done);
        return;
    }
    if (e->max_stack <= BATCH_STACK) {
        d_run_batch(e->code, e->n, n, p, e->t, out);
        return;
    }
    for (size_t i = 0; i < n; i++)
        out[i] = d_run(e->code, e->n, p[3 * i], p[3 * i + 1], p[3 * i + 2], e->t);
}

double geom_implicit_expr_eval_grad(const geom_implicit_expr *e, const double p[3],
                                    double grad[3])
{
    if (!e || !p) {
        if (grad)
            grad[0] = grad[1] = grad[2] = NAN;
        return NAN;
    }
    dual x = {p[0], {1.0, 0.0, 0.0}};
    dual y = {p[1], {0.0, 1.0, 0.0}};
    dual z = {p[2], {0.0, 0.0, 1.0}};
    dual r = g_run(e->code, e->n, x, y, z, g_cst(e->t));
    if (grad) {
        grad[0] = r.d[0];
        grad[1] = r.d[1];
        grad[2] = r.d[2];
    }
    return r.v;
}

/* The distance-shaped programs for gradients: U((x*x + y*y) + z*z) [B c]
 * with each square x*x or x^2, U sqrt or none (uop 0), B one of + - * / or
 * none (bop 0); sphere(c) is sqrt((x^2 + y^2) + z^2) - c. *uop, *bop, *c
 * receive U, B and c. */
static int g_is_len(const geom_implicit_expr *e, int *uop, int *bop, double *c)
{
    const expr_ins *k = e->code;
    size_t n = e->n, i = 0;
    *uop = 0;
    *bop = 0;
    *c = 0.0;
    if (n == 2 && k[0].op == OP_CONST && k[1].op == OP_SPHERE1) {
        *uop = OP_SQRT;
        *bop = OP_SUB;
        *c = k[0].c;
        return 1;
    }
    for (int axis = 0; axis < 3; axis++) {
        int v = OP_X + axis;
        if (i + 2 <= n && k[i].op == v && k[i + 1].op == OP_POWI && k[i + 1].n == 2)
            i += 2;
        else if (i + 3 <= n && k[i].op == v && k[i + 1].op == v && k[i + 2].op == OP_MUL)
            i += 3;
        else
            return 0;
        if (axis > 0 && !(i < n && k[i++].op == OP_ADD))
            return 0;
    }
    if (i < n && k[i].op == OP_SQRT) {
        *uop = OP_SQRT;
        i++;
    }
    if (i + 2 == n && k[i].op == OP_CONST && is_arith(k[i + 1].op)) {
        *bop = k[i + 1].op;
        *c = k[i].c;
        i += 2;
    }
    return i == n;
}

/* A program of g_is_len over n points p into values and grads (3*n; NULL:
 * not wanted), straight from the points, in loops the compiler vectorises.
 * Each point gets g_run's dual operations with the seeds' constant
 * derivatives worked out by hand: x*x (or x^2: g_powi's 2x * 1 is x + x)
 * has the derivatives (x + x, 0 + 0, 0 + 0) and the two additions of the
 * sum of squares leave (x + x) + 0, (y + y) + 0, (z + z) + 0 (a second
 * "+ 0" changes nothing once the first has made a -0 a +0); sqrt(s) gives
 * chain(0.5 / sqrt(s), d); the tail against a constant c: "+ c" adds 0 to
 * each derivative, "- c" subtracts 0 (no change), "* c" is chain(c, d) +
 * chain(v, 0) = chain(c, d) + 0, "/ c" is chain(1 / c, d) - 0. The same
 * operations on the same operands: the same bits (test_implicit_batch). */
#define GL_LOOP(SQRT, EXPR_V, EXPR_D)                                                          \
    for (size_t l = 0; l < XB; l++) {                                                          \
        double x = P[3 * l], y = P[3 * l + 1], z = P[3 * l + 2];                               \
        double v = d_add(d_add(d_mul(x, x), d_mul(y, y)), d_mul(z, z));                        \
        double d0 = d_add(d_add(x, x), 0.0), d1 = d_add(d_add(y, y), 0.0);                     \
        double d2 = d_add(d_add(z, z), 0.0);                                                   \
        if (SQRT) {                                                                            \
            v = d_sqrt(v);                                                                     \
            double fp = d_div(0.5, v);                                                         \
            d0 = chain(fp, d0);                                                             \
            d1 = chain(fp, d1);                                                             \
            d2 = chain(fp, d2);                                                             \
        }                                                                                      \
        V[l] = (EXPR_V);                                                                       \
        G[3 * l] = EXPR_D(d0);                                                                 \
        G[3 * l + 1] = EXPR_D(d1);                                                             \
        G[3 * l + 2] = EXPR_D(d2);                                                             \
    }
#define GL_ADD(d) d_add(d, 0.0)
#define GL_SAME(d) (d)
#define GL_MUL(d) d_add(chain(c, d), 0.0)
#define GL_DIV(d) chain(ic, d)
#define GL_TAIL(SQRT)                                                                          \
    do {                                                                                       \
        if (bop == OP_ADD)                                                                     \
            GL_LOOP(SQRT, d_add(v, c), GL_ADD)                                                 \
        else if (bop == OP_SUB)                                                                \
            GL_LOOP(SQRT, d_sub(v, c), GL_SAME)                                                \
        else if (bop == OP_MUL)                                                                \
            GL_LOOP(SQRT, d_mul(v, c), GL_MUL)                                                 \
        else if (bop == OP_DIV)                                                                \
            GL_LOOP(SQRT, d_div(v, c), GL_DIV)                                                 \
        else                                                                                   \
            GL_LOOP(SQRT, v, GL_SAME)                                                          \
    } while (0)
/* One block of XB points P into V and G (a constant trip count: the loops
 * vectorise). */
GEOM__CLONE_INLINE void g_len_block(int uop, int bop, double c, double ic,
                                    const double *restrict P, double *restrict V,
                                    double *restrict G)
{
    if (uop == OP_SQRT)
        GL_TAIL(1);
    else
        GL_TAIL(0);
}
GEOM_SIMD_CLONES
static void g_run_len(int uop, int bop, double c, size_t n, const double *restrict p,
                      double *restrict values, double *restrict grads)
{
    _Alignas(64) double gt[3 * XB], pt[3 * XB], vt[XB];
    double ic = d_div(1.0, c);
    size_t full = n / XB * XB;
    for (size_t b0 = 0; b0 < full; b0 += XB)
        g_len_block(uop, bop, c, ic, p + 3 * b0, values + b0, grads ? grads + 3 * b0 : gt);
    if (full == n)
        return;
    size_t L = n - full; /* the tail, padded with zeros */
    memset(pt, 0, sizeof pt);
    memcpy(pt, p + 3 * full, 3 * L * sizeof(double));
    g_len_block(uop, bop, c, ic, pt, vt, gt);
    memcpy(values + full, vt, L * sizeof(double));
    if (grads)
        memcpy(grads + 3 * full, gt, 3 * L * sizeof(double));
}
#undef GL_TAIL
#undef GL_DIV
#undef GL_MUL
#undef GL_SAME
#undef GL_ADD
#undef GL_LOOP

/* Blocks of GB points for the other programs: the program is unrolled once
 * per call into steps of the elementary dual operations (expr_template.h
 * instantiated over s_*, a type that records instead of computing: the
 * primitives, smin and clamp become their g_* operations in the order g_run
 * does them). Each step applies one g_* function lane by lane over GB
 * points whose four components (value, d/dx, d/dy, d/dz) lie in separate
 * arrays (a buffer of glanes), in a loop the compiler vectorises; an
 * operation on constants only is done once, as g_run does it; x, y and z
 * are buffers of the points' coordinates and the seeds' unit and zero
 * derivatives. Every lane does exactly g_run's operations: bitwise g_run.
 * The lengths the shapes are made of, sqrt(sqr(a) + sqr(b)) and
 * sqrt((sqr(a) + sqr(b)) + sqr(c)), are one step each (G_LEN2, G_LEN3:
 * the same g_* operations, without the memory round trips between them);
 * the sine and the cosine of the same operand (the gyroids) are one step
 * with two results (G_SINCOS), so each lane calls sincos once for both. */
enum { GB = 32, G_SQR = OP_COUNT, G_LEN2, G_LEN3, G_SINCOS }; /* not opcodes */
typedef double glanes[4][GB];

/* op applied to a (and b): EXPR of a, b and n (OP_POWI's exponent) */
#define G_OPS(X)                                                                               \
    X(OP_ADD, g_add(a, b)) X(OP_SUB, g_sub(a, b)) X(OP_MUL, g_mul(a, b))                       \
    X(OP_DIV, g_div(a, b)) X(OP_POW, g_pow(a, b)) X(OP_MIN, g_min(a, b))                       \
    X(OP_MAX, g_max(a, b)) X(OP_ATAN2, g_atan2(a, b)) X(OP_NEG, g_neg(a))                      \
    X(G_SQR, g_sqr(a)) X(OP_SQRT, g_sqrt(a)) X(OP_ABS, g_abs(a)) X(OP_SIN, g_sin(a))           \
    X(OP_COS, g_cos(a)) X(OP_TAN, g_tan(a)) X(OP_EXP, g_exp(a)) X(OP_LOG, g_log(a))

static dual g_apply(int op, int n, dual a, dual b)
{
#define G_APPLY(OP, EXPR)                                                                      \
    case OP: return EXPR;
    switch (op) {
    G_OPS(G_APPLY)
    case OP_POWI: return g_powi(a, n);
    default: return g_nan();
    }
#undef G_APPLY
}

/* One step over GB lanes: the glanes A, B and C (B, C = A for a unary op,
 * C = A for a binary one) into R (and R2, G_SINCOS's cosine). */
GEOM__CLONE_INLINE void g_lanes(int op, int n, const double *restrict A, const double *restrict B,
                                const double *restrict C, double *restrict R,
                                double *restrict R2)
{
#define G_LOAD(X, x) dual x = {X[l], {X[GB + l], X[2 * GB + l], X[3 * GB + l]}}
#define G_STORE(X, x)                                                                          \
    do {                                                                                       \
        X[l] = x.v;                                                                            \
        X[GB + l] = x.d[0];                                                                    \
        X[2 * GB + l] = x.d[1];                                                                \
        X[3 * GB + l] = x.d[2];                                                                \
    } while (0)
#define G_LANES(EXPR)                                                                          \
    for (int l = 0; l < GB; l++) {                                                             \
        G_LOAD(A, a);                                                                          \
        G_LOAD(B, b);                                                                          \
        G_LOAD(C, c);                                                                          \
        dual r = (EXPR);                                                                       \
        (void)b;                                                                               \
        (void)c;                                                                               \
        G_STORE(R, r);                                                                         \
    }
#define G_CASE(OP, EXPR)                                                                       \
    case OP: G_LANES(EXPR) break;
    switch (op) {
    G_OPS(G_CASE)
    G_CASE(G_LEN2, g_sqrt(g_add(g_sqr(a), g_sqr(b))))
    G_CASE(G_LEN3, g_sqrt(g_add(g_add(g_sqr(a), g_sqr(b)), g_sqr(c))))
    case OP_POWI:
        if (n == 2)
            G_LANES(g_powi(a, 2))
        else
            G_LANES(g_powi(a, n))
        break;
    case G_SINCOS:
        for (int l = 0; l < GB; l++) {
            G_LOAD(A, a);
            dual r = g_sin(a), r2 = g_cos(a);
            G_STORE(R, r);
            G_STORE(R2, r2);
        }
        break;
    default: break;
    }
#undef G_CASE
#undef G_LANES
#undef G_STORE
#undef G_LOAD
}

/* The recorder: a value is a constant (g NULL, its dual c) or the id of a
 * buffer's lanes: 0, 1, 2 the seeds x, y, z, then constants used as lane
 * operands and the steps' results. */
typedef struct gstep {
    int op, n, a, b, c, r, r2; /* r2: G_SINCOS's cosine, else -1 */
} gstep;
typedef struct gval {
    dual c;   /* a constant's value (the seeds: 0) */
    int last; /* the last step reading it */
    int buf;  /* its buffer (-3: an intermediate of a fused step) */
    int free; /* -1 a seed or constant, 1 a step's result freed after its
               * last use, 0 the program's result */
} gval;
typedef struct grec {
    const geom_allocator *alloc;
    gstep *step;
    gval *val;
    size_t ns, cs, nv, cv;
    int fail;
} grec;
typedef struct gsym {
    grec *g; /* NULL: the constant c */
    int id;
    dual c;
} gsym;

static int s_id(grec *g, gsym a)
{
    if (a.g)
        return a.id;
    gval v = {a.c, -1, 0, -1};
    if (geom__push(g->alloc, (void **)&g->val, &g->nv, &g->cv, sizeof v, &v) != GEOM_OK)
        g->fail = 1;
    return (int)g->nv - 1;
}
static gsym s_op(int op, int n, gsym a, gsym b)
{
    gsym r = {a.g ? a.g : b.g, 0, g_cst(NAN)};
    if (!r.g) { /* constants only */
        r.c = g_apply(op, n, a.c, b.c);
        return r;
    }
    grec *g = r.g;
    gstep s = {op, n, s_id(g, a), s_id(g, b), 0, 0, -1};
    s.c = s.a;
    gval v = {g_cst(NAN), -1, 0, 1};
    if (g->fail || geom__push(g->alloc, (void **)&g->val, &g->nv, &g->cv, sizeof v, &v) != GEOM_OK)
        g->fail = 1;
    s.r = r.id = (int)g->nv - 1;
    if (g->fail || geom__push(g->alloc, (void **)&g->step, &g->ns, &g->cs, sizeof s, &s) != GEOM_OK)
        g->fail = 1;
    return r;
}
static gsym s_cst(double c)
{
    gsym r = {NULL, 0, g_cst(c)};
    return r;
}
#define S_BINARY(name, OP)                                                                     \
    static gsym s_##name(gsym a, gsym b) { return s_op(OP, 0, a, b); }
#define S_UNARY(name, OP)                                                                      \
    static gsym s_##name(gsym a) { return s_op(OP, 0, a, a); }
S_BINARY(add, OP_ADD)
S_BINARY(sub, OP_SUB)
S_BINARY(mul, OP_MUL)
S_BINARY(div, OP_DIV)
S_BINARY(pow, OP_POW)
S_BINARY(min, OP_MIN)
S_BINARY(max, OP_MAX)
S_BINARY(atan2, OP_ATAN2)
S_UNARY(neg, OP_NEG)
S_UNARY(sqr, G_SQR)
S_UNARY(abs, OP_ABS)
S_UNARY(tan, OP_TAN)
S_UNARY(exp, OP_EXP)
S_UNARY(log, OP_LOG)
#undef S_UNARY
#undef S_BINARY
static gsym s_powi(gsym a, int n) { return s_op(OP_POWI, n, a, a); }

/* sin(a) or cos(a) (op): when a step already takes the other of a, it
 * becomes G_SINCOS and gives this one as well. */
static gsym s_trig(int op, gsym a)
{
    grec *g = a.g;
    for (size_t j = g && !g->fail ? g->ns : 0; j-- > 0;) {
        if (g->step[j].op != (op == OP_SIN ? OP_COS : OP_SIN) || g->step[j].a != a.id)
            continue;
        gval v = {g_cst(NAN), -1, 0, 1};
        if (geom__push(g->alloc, (void **)&g->val, &g->nv, &g->cv, sizeof v, &v) != GEOM_OK) {
            g->fail = 1;
            break;
        }
        gstep *s = &g->step[j];
        gsym r = {g, (int)g->nv - 1, g_cst(NAN)};
        s->r2 = op == OP_COS ? r.id : s->r;
        s->r = op == OP_COS ? s->r : r.id;
        s->op = G_SINCOS;
        return r;
    }
    return s_op(op, 0, a, a);
}
static gsym s_sin(gsym a) { return s_trig(OP_SIN, a); }
static gsym s_cos(gsym a) { return s_trig(OP_COS, a); }

/* The step among g's steps from on whose result is id, or NULL. */
static gstep *s_producer(grec *g, int id, size_t from)
{
    for (size_t j = from; j < g->ns; j++)
        if (g->step[j].r == id)
            return &g->step[j];
    return NULL;
}
/* sqrt(a), and when the steps just before it are the squares and sums of
 * a length (len2, len3: their results used by nothing else, as in the
 * template), those steps and the sqrt become one G_LEN2 or G_LEN3 step. */
static gsym s_sqrt(gsym a)
{
    gsym r = s_op(OP_SQRT, 0, a, a);
    grec *g = r.g;
    if (!g || g->fail)
        return r;
    for (size_t m = 3; m <= 5; m += 2) { /* the steps before the sqrt */
        if (g->ns < m + 1)
            break;
        size_t from = g->ns - 1 - m;
        gstep *sq = &g->step[g->ns - 1], *add = s_producer(g, sq->a, from), *in = add;
        if (!add || add->op != OP_ADD)
            break;
        gstep *s3 = NULL;
        if (m == 5) {
            in = s_producer(g, add->a, from);
            s3 = s_producer(g, add->b, from);
            if (!in || in->op != OP_ADD || !s3 || s3->op != G_SQR)
                continue;
        }
        gstep *s1 = s_producer(g, in->a, from), *s2 = s_producer(g, in->b, from);
        if (!s1 || !s2 || s1 == s2 || s1->op != G_SQR || s2->op != G_SQR)
            continue;
        /* the squares' operands come from before these steps */
        if (s_producer(g, s1->a, from) || s_producer(g, s2->a, from) ||
            (s3 && s_producer(g, s3->a, from)))
            break;
        gstep f = {m == 3 ? G_LEN2 : G_LEN3, 0, s1->a, s2->a, s3 ? s3->a : s1->a, sq->r, -1};
        gstep *dead[] = {s1, s2, add, in, s3};
        for (size_t k = 0; k < m; k++)
            g->val[dead[k]->r].buf = -3;
        g->ns -= m + 1;
        g->step[g->ns++] = f;
        break;
    }
    return r;
}

#define NUM gsym
#define F(name) s_##name
#include "implicit/expr_template.h"
#undef NUM
#undef F

/* L points P (3*L doubles) into the lanes X, Y, Z; L lanes of R (glanes)
 * into V and G (3*L doubles, NULL: not wanted). */
GEOM__CLONE_INLINE void g_load(size_t L, const double *restrict P, double *restrict X,
                               double *restrict Y, double *restrict Z)
{
    for (size_t l = 0; l < L; l++) {
        X[l] = P[3 * l];
        Y[l] = P[3 * l + 1];
        Z[l] = P[3 * l + 2];
    }
}
GEOM__CLONE_INLINE void g_store(size_t L, const double *restrict R, double *restrict V,
                                double *restrict G)
{
    for (size_t l = 0; l < L; l++)
        V[l] = R[l];
    if (G)
        for (size_t l = 0; l < L; l++) {
            G[3 * l] = R[GB + l];
            G[3 * l + 1] = R[2 * GB + l];
            G[3 * l + 2] = R[3 * GB + l];
        }
}

/* GB points at a time: the seeds' coordinates into buffers 0, 1, 2 (the
 * tail's missing points are zeros), the steps, the result's buffer res out
 * (the program has at least one step). */
GEOM_SIMD_CLONES
static void g_blocks(const gstep *step, size_t ns, glanes *buf, int res, size_t n,
                     const double *p, double *values, double *grads)
{
    for (size_t b0 = 0; b0 < n; b0 += GB) {
        size_t L = n - b0 < GB ? n - b0 : GB;
        if (L == GB) {
            g_load(GB, p + 3 * b0, buf[0][0], buf[1][0], buf[2][0]);
        } else {
            for (int q = 0; q < 3; q++)
                memset(buf[q][0], 0, sizeof buf[q][0]);
            g_load(L, p + 3 * b0, buf[0][0], buf[1][0], buf[2][0]);
        }
        for (size_t j = 0; j < ns; j++) {
            const gstep *s = &step[j];
            g_lanes(s->op, s->n, buf[s->a][0], buf[s->b][0], buf[s->c][0], buf[s->r][0],
                    buf[s->r2 >= 0 ? s->r2 : s->r][0]);
        }
        double *G = grads ? grads + 3 * b0 : NULL;
        if (L == GB)
            g_store(GB, buf[res][0], values + b0, G);
        else
            g_store(L, buf[res][0], values + b0, G);
    }
}

/* The program of e over n points p into values and grads (NULL: not
 * wanted); 0 (nothing written) when the memory cannot be allocated. */
static int g_run_blocks(const geom_implicit_expr *e, size_t n, const double *p, double *values,
                        double *grads)
{
    grec g = {&e->alloc, NULL, NULL, 0, 0, 0, 0, 0};
    gsym seed[3];
    for (int i = 0; i < 3; i++) {
        gsym s = {&g, s_id(&g, s_cst(0.0)), g_cst(0.0)};
        seed[i] = s;
    }
    gsym r = s_run(e->code, e->n, seed[0], seed[1], seed[2], s_cst(e->t));
    int ok = 0, *free_buf = NULL, nb = 0, nfree = 0;
    size_t bytes = 0;
    char *raw = NULL;
    if (!r.g || !g.ns) /* a constant or x, y, z: no steps, done point by point */
        goto done;
    if (g.fail || !(free_buf = geom__alloc(&e->alloc, (g.nv + 1) * sizeof(int))))
        goto done;
    /* buffers: the seeds and the constants have their own; a step's result
     * takes a free one (none its operands use: the lanes are restrict) and
     * the step frees its operands' after their last use */
    for (size_t j = 0; j < g.ns; j++) {
        g.val[g.step[j].r].buf = -1;
        if (g.step[j].r2 >= 0)
            g.val[g.step[j].r2].buf = -1;
    }
    for (size_t j = 0; j < g.ns; j++) {
        g.val[g.step[j].a].last = (int)j;
        g.val[g.step[j].b].last = (int)j;
        g.val[g.step[j].c].last = (int)j;
    }
    for (size_t i = 0; i < g.nv; i++)
        if (g.val[i].buf == 0)
            g.val[i].buf = nb++;
    for (size_t j = 0; j < g.ns; j++) {
        gstep *s = &g.step[j];
        gval *v = &g.val[s->r];
        v->buf = nfree ? free_buf[--nfree] : nb++;
        v->free = s->r != r.id;
        if (s->r2 >= 0) {
            gval *v2 = &g.val[s->r2];
            v2->buf = nfree ? free_buf[--nfree] : nb++;
            v2->free = s->r2 != r.id;
        }
        int ops[3] = {s->a, s->b, s->c};
        for (int q = 0; q < 3; q++) {
            gval *o = &g.val[ops[q]];
            if (o->free == 1 && o->last == (int)j && (q < 1 || ops[q] != ops[0]) &&
                (q < 2 || ops[q] != ops[1]))
                free_buf[nfree++] = o->buf;
        }
    }
    bytes = (size_t)nb * sizeof(glanes) + 64;
    if (!(raw = geom__alloc(&e->alloc, bytes)))
        goto done;
    glanes *buf = (glanes *)(void *)(raw + (64 - (uintptr_t)raw % 64) % 64);
    for (size_t i = 0; i < g.nv; i++) { /* the seeds' derivatives, the constants */
        if (g.val[i].free >= 0)
            continue;
        const dual *c = &g.val[i].c;
        double comp[4] = {c->v, c->d[0], c->d[1], c->d[2]};
        if (i < 3)
            comp[1 + i] = 1.0;
        for (int m = 0; m < 4; m++)
            for (int l = 0; l < GB; l++)
                buf[g.val[i].buf][m][l] = comp[m];
    }
    for (size_t j = 0; j < g.ns; j++) {
        gstep *s = &g.step[j];
        s->a = g.val[s->a].buf;
        s->b = g.val[s->b].buf;
        s->c = g.val[s->c].buf;
        s->r = g.val[s->r].buf;
        if (s->r2 >= 0)
            s->r2 = g.val[s->r2].buf;
    }
    g_blocks(g.step, g.ns, buf, g.val[r.id].buf, n, p, values, grads);
    ok = 1;
done:
    geom__free(&e->alloc, raw, bytes);
    geom__free(&e->alloc, free_buf, (g.nv + 1) * sizeof(int));
    geom__free(&e->alloc, g.step, g.cs * sizeof(gstep));
    geom__free(&e->alloc, g.val, g.cv * sizeof(gval));
    return ok;
}

void geom_implicit_expr_eval_grad_many(const geom_implicit_expr *e, size_t n, const double *p,
                                       double *values, double *grads)
{
    if (!values)
        return;
    if (!e || (!p && n > 0)) {
        for (size_t i = 0; i < n; i++) {
            values[i] = NAN;
            if (grads)
                grads[3 * i] = grads[3 * i + 1] = grads[3 * i + 2] = NAN;
        }
        return;
    }
    int uop, bop;
    double c;
    if (g_is_len(e, &uop, &bop, &c)) {
        g_run_len(uop, bop, c, n, p, values, grads);
        return;
    }
    if (n > 0 && g_run_blocks(e, n, p, values, grads))
        return;
    for (size_t i = 0; i < n; i++) {
        double g[3];
        values[i] = geom_implicit_expr_eval_grad(e, p + 3 * i, g);
        if (grads)
            memcpy(grads + 3 * i, g, sizeof g);
    }
}

geom_status geom_implicit_expr_eval_interval(const geom_implicit_expr *e, const double lo[3],
                                             const double hi[3], double out[2])
{
    if (out)
        out[0] = out[1] = NAN;
    if (!e || !lo || !hi || !out)
        return GEOM_ERR_INVALID_ARG;
    for (int i = 0; i < 3; i++)
        if (isnan(lo[i]) || isnan(hi[i]) || lo[i] > hi[i])
            return GEOM_ERR_INVALID_ARG;
    ival r = i_run(e->code, e->n, iv_make(lo[0], hi[0]), iv_make(lo[1], hi[1]),
                   iv_make(lo[2], hi[2]), i_cst(e->t));
    out[0] = r.lo;
    out[1] = r.hi;
    if (iv_isempty(r))
        out[0] = out[1] = NAN;
    return GEOM_OK;
}

geom_status geom_implicit_expr_eval_bounds(const geom_implicit_expr *e, const double lo[3],
                                           const double hi[3], double out[2], int *defined)
{
    if (defined)
        *defined = 0;
    if (out)
        out[0] = out[1] = NAN;
    if (!e || !lo || !hi || !out || !defined)
        return GEOM_ERR_INVALID_ARG;
    for (int i = 0; i < 3; i++)
        if (isnan(lo[i]) || isnan(hi[i]) || lo[i] > hi[i])
            return GEOM_ERR_INVALID_ARG;
    ivn x = n_mk(iv_make(lo[0], hi[0]), 0), y = n_mk(iv_make(lo[1], hi[1]), 0);
    ivn z = n_mk(iv_make(lo[2], hi[2]), 0);
    ivn r = n_run(e->code, e->n, x, y, z, n_cst(e->t));
    if (iv_isempty(r.v))
        return GEOM_OK;
    out[0] = r.v.lo;
    out[1] = r.v.hi;
    *defined = !r.nan;
    return GEOM_OK;
}

geom_status geom_implicit_expr_eval_bounds_many(const geom_implicit_expr *e, size_t n,
                                                const double *lo, const double *hi, double *out,
                                                int *defined)
{
    if (n == 0)
        return GEOM_OK;
    if (!e || !lo || !hi || !out || !defined)
        return GEOM_ERR_INVALID_ARG;
    geom_status st = GEOM_OK;
    for (size_t i = 0; i < n; i++)
        if (geom_implicit_expr_eval_bounds(e, lo + 3 * i, hi + 3 * i, out + 2 * i, defined + i))
            st = GEOM_ERR_INVALID_ARG;
    return st;
}

double geom_implicit_expr_value_cb(void *user, const double p[3])
{
    return geom_implicit_expr_eval((const geom_implicit_expr *)user, p);
}

double geom_implicit_expr_grad_cb(void *user, const double p[3], double grad[3])
{
    return geom_implicit_expr_eval_grad((const geom_implicit_expr *)user, p, grad);
}

static void expr_values_cb(void *user, size_t n, const double *p, double *out)
{
    geom_implicit_expr_eval_many((const geom_implicit_expr *)user, n, p, out);
}

static void expr_gradients_cb(void *user, size_t n, const double *p, double *values,
                              double *grads)
{
    geom_implicit_expr_eval_grad_many((const geom_implicit_expr *)user, n, p, values, grads);
}

/* Rigorous bounds only over boxes where the expression is defined and
 * finite everywhere (geom_implicit_bounds_fn's contract). */
static int expr_bounds_cb(void *user, const double lo[3], const double hi[3], double out[2])
{
    int defined = 0;
    if (geom_implicit_expr_eval_bounds((const geom_implicit_expr *)user, lo, hi, out, &defined) !=
        GEOM_OK)
        return 0;
    return defined && !isnan(out[0]) && !isnan(out[1]);
}

void geom_implicit_field_from_expr(const geom_implicit_expr *e, geom_implicit_field *out)
{
    if (!out)
        return;
    memset(out, 0, sizeof *out);
    out->value = geom_implicit_expr_value_cb;
    out->gradient = geom_implicit_expr_grad_cb;
    out->values = expr_values_cb;
    out->gradients = expr_gradients_cb;
    out->bounds = expr_bounds_cb;
    out->user = (void *)(uintptr_t)e;
    out->exact = 1;
}

/* ============================================================ grid rows */

/* For marching cubes' sampling of an expression (iso/extract.c): the nodes
 * of a grid row share y and z, so the block evaluator runs a plan made
 * with y and z constants (x_plan with yz): an operation on y, z and
 * constants alone is done once per row on the scalars, and the primitives
 * whose arguments are constants run as one lane loop each (row_prim),
 * their y and z terms computed once. The plan is made once (its shape
 * does not depend on y and z); x_plan records on a tape the operations
 * that fold constants of the row, and which steps, constant lanes and
 * result take them; each row replays the tape (x_bind: the same d_*
 * operations on the same operands as a plan made for that row) and runs
 * the steps. Every lane does exactly d_run's operations on the same
 * operands: bitwise d_run. */
struct geom__expr_rows {
    const geom_implicit_expr *e;
    const geom_allocator *alloc;
    void *raw;
    size_t bytes;
    int planned; /* 0: the program is deeper than the block stack */
    xwork *w;
    xstep *plan;
    size_t ns;
    xrec rec;
    double *u; /* the row's constants: y, z, then the tape's values */
    const double *res;
    double res_c;
};

geom_status geom__implicit_expr_rows_create(const geom_implicit_expr *e,
                                            const geom_allocator *a, geom__expr_rows **out)
{
    *out = NULL;
    size_t m = e->n ? e->n : 1;
    size_t off_w = (sizeof(geom__expr_rows) + 63) / 64 * 64;
    size_t off_plan = off_w + sizeof(xwork);
    size_t off_tape = off_plan + m * sizeof(xstep);
    size_t off_u = off_tape + m * sizeof(xtape);
    size_t bytes = off_u + (m + 2) * sizeof(double) + 64;
    char *raw = geom__alloc(a, bytes);
    if (!raw)
        return GEOM_ERR_NOMEM;
    char *base = raw + (64 - (uintptr_t)raw % 64) % 64;
    geom__expr_rows *r = (geom__expr_rows *)(void *)base;
    memset(r, 0, sizeof *r);
    r->e = e;
    r->alloc = a;
    r->raw = raw;
    r->bytes = bytes;
    r->w = (xwork *)(void *)(base + off_w);
    r->plan = (xstep *)(void *)(base + off_plan);
    r->rec.tape = (xtape *)(void *)(base + off_tape);
    r->u = (double *)(void *)(base + off_u);
    if (e->max_stack <= XSTACK) {
        const double yz[2] = {0.0, 0.0};
        r->ns = x_plan(e->code, e->n, e->t, yz, r->w, r->plan, &r->res, &r->res_c, &r->rec);
        r->ns = x_fuse(r->plan, r->ns, r->w, &r->rec);
        r->planned = 1;
    }
    *out = r;
    return GEOM_OK;
}

void geom__implicit_expr_rows_destroy(geom__expr_rows *r)
{
    if (r)
        geom__free(r->alloc, r->raw, r->bytes);
}

/* The constants of the row (y, z) into the plan: the tape replayed, then
 * the steps' tagged constants, the constant lanes, y and z lanes and the
 * constant result. */
static void x_bind(geom__expr_rows *r, double y, double z)
{
    double *u = r->u;
    const xrec *rec = &r->rec;
    u[0] = y;
    u[1] = z;
    for (size_t i = 0; i < rec->ntape; i++) {
        const xtape *t = &rec->tape[i];
        double a[3] = {0.0, 0.0, 0.0};
        for (int q = 0; q < t->kind; q++)
            a[q] = t->t[q] ? u[t->t[q] - 1] : t->c[q];
        u[2 + i] = t->kind == 1   ? d_scalar_unary(t->in, a[0])
                   : t->kind == 2 ? d_scalar_binary(t->op, a[0], a[1])
                                  : x_fold3(t->op, a[0], a[1], a[2]);
    }
    for (size_t j = 0; j < r->ns; j++) {
        xstep *s = &r->plan[j];
        if (s->ta)
            s->ca = u[s->ta - 1];
        if (s->tb)
            s->cb = u[s->tb - 1];
        if (s->kind == XK_ROW_PRIM)
            for (int q = 0; q < s->k; q++)
                if (s->at[q])
                    s->a[q] = u[s->at[q] - 1];
    }
    for (size_t q = 0; q < rec->nkc; q++)
        if (rec->kc_tag[q])
            for (int l = 0; l < XB; l++)
                r->w->kc[q][l] = u[rec->kc_tag[q] - 1];
    if (rec->fill_yz)
        for (int l = 0; l < XB; l++) {
            r->w->Y[l] = y;
            r->w->Z[l] = z;
        }
    if (rec->res_tag)
        r->res_c = u[rec->res_tag - 1];
}

void geom__implicit_expr_rows(geom__expr_rows *r, size_t n, const double *x, double y, double z,
                              double *out)
{
    if (n == 0)
        return;
    const geom_implicit_expr *e = r->e;
    if (!r->planned) {
        for (size_t i = 0; i < n; i++)
            out[i] = d_run(e->code, e->n, x[i], y, z, e->t);
        return;
    }
    x_bind(r, y, z);
    if (n >= XB) {
        d_run_blocks(r->plan, r->ns, r->w, r->res, r->res_c, n, x, 1, out, 0);
        return;
    }
    double xs[XB], os[XB]; /* a short row, padded with its last point */
    for (size_t i = 0; i < XB; i++)
        xs[i] = x[i < n ? i : n - 1];
    d_run_blocks(r->plan, r->ns, r->w, r->res, r->res_c, XB, xs, 1, os, 0);
    memcpy(out, os, n * sizeof(double));
}

void geom__implicit_expr_row(const geom_implicit_expr *e, size_t n, const double *x, double y,
                             double z, double *out)
{
    geom__expr_rows *r = NULL;
    if (geom__implicit_expr_rows_create(e, NULL, &r) == GEOM_OK) {
        geom__implicit_expr_rows(r, n, x, y, z, out);
        geom__implicit_expr_rows_destroy(r);
        return;
    }
    for (size_t i = 0; i < n; i++)
        out[i] = d_run(e->code, e->n, x[i], y, z, e->t);
}
