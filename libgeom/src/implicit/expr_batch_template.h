/*
 * The batch interpreter, written once over a numeric type like
 * expr_template.h and instantiated for double (values) by expr_eval.c (the
 * gradients have blocks of their own): the program runs over up to
 * BATCH_LANES points at a time, so the dispatch is paid once per
 * instruction and lane group, and simple operations become loops the
 * compiler vectorises. Each lane does exactly what F(run) does, so the
 * results are identical to single-point evaluation. Before including,
 * define NUM, F(name) (as for expr_template.h, included first),
 * BATCH_LANES and BATCH_STACK (the program's max_stack must not exceed it).
 *
 * F(run_lanes): L <= BATCH_LANES points with coordinates X[l], Y[l], Z[l]
 * and time t; res[l] receives the value at point l.
 */
static void F(run_lanes)(const expr_ins *code, size_t ncode, size_t L, const NUM *X, const NUM *Y,
                         const NUM *Z, NUM t, NUM *res)
{
    NUM st[BATCH_STACK][BATCH_LANES];
    NUM args[8];
    size_t sp = 0, l;
    for (l = 0; l < L; l++)
        st[0][l] = F(cst)(NAN);
    for (size_t i = 0; i < ncode; i++) {
        const expr_ins *in = &code[i];
        NUM *a = sp >= 1 ? st[sp - 1] : NULL, *b = sp >= 2 ? st[sp - 2] : NULL;
        switch ((expr_op)in->op) {
        case OP_CONST:
            for (l = 0; l < L; l++)
                st[sp][l] = F(cst)(in->c);
            sp++;
            break;
        case OP_X: for (l = 0; l < L; l++) st[sp][l] = X[l]; sp++; break;
        case OP_Y: for (l = 0; l < L; l++) st[sp][l] = Y[l]; sp++; break;
        case OP_Z: for (l = 0; l < L; l++) st[sp][l] = Z[l]; sp++; break;
        case OP_T: for (l = 0; l < L; l++) st[sp][l] = t; sp++; break;
        case OP_ADD: for (l = 0; l < L; l++) b[l] = F(add)(b[l], a[l]); sp--; break;
        case OP_SUB: for (l = 0; l < L; l++) b[l] = F(sub)(b[l], a[l]); sp--; break;
        case OP_MUL: for (l = 0; l < L; l++) b[l] = F(mul)(b[l], a[l]); sp--; break;
        case OP_DIV: for (l = 0; l < L; l++) b[l] = F(div)(b[l], a[l]); sp--; break;
        case OP_NEG: for (l = 0; l < L; l++) a[l] = F(neg)(a[l]); break;
        case OP_POW: for (l = 0; l < L; l++) b[l] = F(pow)(b[l], a[l]); sp--; break;
        case OP_POWI:
            if (in->n == 2) /* the same as powi(a, 2), without its branches */
                for (l = 0; l < L; l++)
                    a[l] = F(sqr)(a[l]);
            else
                for (l = 0; l < L; l++)
                    a[l] = F(powi)(a[l], in->n);
            break;
        case OP_SQRT: for (l = 0; l < L; l++) a[l] = F(sqrt)(a[l]); break;
        case OP_ABS: for (l = 0; l < L; l++) a[l] = F(abs)(a[l]); break;
        case OP_SIN: for (l = 0; l < L; l++) a[l] = F(sin)(a[l]); break;
        case OP_COS: for (l = 0; l < L; l++) a[l] = F(cos)(a[l]); break;
        case OP_TAN: for (l = 0; l < L; l++) a[l] = F(tan)(a[l]); break;
        case OP_EXP: for (l = 0; l < L; l++) a[l] = F(exp)(a[l]); break;
        case OP_LOG: for (l = 0; l < L; l++) a[l] = F(log)(a[l]); break;
        case OP_MIN: for (l = 0; l < L; l++) b[l] = F(min)(b[l], a[l]); sp--; break;
        case OP_MAX: for (l = 0; l < L; l++) b[l] = F(max)(b[l], a[l]); sp--; break;
        case OP_ATAN2: for (l = 0; l < L; l++) b[l] = F(atan2)(b[l], a[l]); sp--; break;
        case OP_CLAMP:
            for (l = 0; l < L; l++)
                st[sp - 3][l] = F(clamp)(st[sp - 3][l], b[l], a[l]);
            sp -= 2;
            break;
        case OP_SMIN:
            for (l = 0; l < L; l++)
                st[sp - 3][l] = F(smin)(st[sp - 3][l], b[l], a[l]);
            sp -= 2;
            break;
        case OP_SMAX:
            for (l = 0; l < L; l++)
                st[sp - 3][l] = F(neg)(F(smin)(F(neg)(st[sp - 3][l]), F(neg)(b[l]), a[l]));
            sp -= 2;
            break;
        case OP_COUNT:
            break;
        default: { /* primitives */
            size_t k = (size_t)geom__implicit_op_arity(in->op);
            size_t first = sp - k;
            for (l = 0; l < L; l++) {
                for (size_t q = 0; q < k; q++)
                    args[q] = st[first + q][l];
                st[first][l] = F(prim)(in->op, X[l], Y[l], Z[l], k ? args : NULL);
            }
            sp = first + 1;
            break;
        }
        }
    }
    for (l = 0; l < L; l++)
        res[l] = st[0][l];
}
