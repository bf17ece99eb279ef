/*
 * The primitives and the program interpreter, written once over a numeric
 * type and instantiated for double (values), dual numbers (gradients) and
 * intervals (bounds) by expr_eval.c. Before including, define
 *   NUM      the type,
 *   F(name)  the prefixed name of an operation on NUM,
 * and provide F(cst) F(add) F(sub) F(mul) F(div) F(neg) F(sqr) F(powi)
 * F(pow) F(sqrt) F(abs) F(sin) F(cos) F(tan) F(exp) F(log) F(min) F(max)
 * F(atan2). Every instantiation evaluates the same sequence of operations,
 * which is what makes the interval bounds enclose the point values (and
 * the recorder s_* of the gradient batch record g_run's operations).
 */

static NUM F(len2)(NUM a, NUM b)
{
    return F(sqrt)(F(add)(F(sqr)(a), F(sqr)(b)));
}

static NUM F(len3)(NUM a, NUM b, NUM c)
{
    return F(sqrt)(F(add)(F(add)(F(sqr)(a), F(sqr)(b)), F(sqr)(c)));
}

/* Quadratic polynomial smooth minimum (Quilez):
 * min(a, b) - max(k - |a - b|, 0)^2 / (4 max(k, DBL_MIN)). */
static NUM F(smin)(NUM a, NUM b, NUM k)
{
    NUM h = F(max)(F(sub)(k, F(abs)(F(sub)(a, b))), F(cst)(0.0));
    NUM den = F(mul)(F(cst)(4.0), F(max)(k, F(cst)(DBL_MIN)));
    return F(sub)(F(min)(a, b), F(div)(F(sqr)(h), den));
}

static NUM F(clamp)(NUM v, NUM lo, NUM hi)
{
    return F(min)(F(max)(v, lo), hi);
}

static NUM F(ellipsoid)(NUM qx, NUM qy, NUM qz, NUM a, NUM b, NUM c)
{
    NUM l = F(len3)(F(div)(qx, a), F(div)(qy, b), F(div)(qz, c));
    return F(mul)(F(sub)(l, F(cst)(1.0)), F(min)(F(min)(a, b), c));
}

static NUM F(torus)(NUM qx, NUM qy, NUM qz, NUM R, NUM r)
{
    return F(sub)(F(len2)(F(sub)(F(len2)(qx, qy), R), qz), r);
}

static NUM F(box)(NUM qx, NUM qy, NUM qz, NUM hx, NUM hy, NUM hz)
{
    NUM zero = F(cst)(0.0);
    NUM dx = F(sub)(F(abs)(qx), hx);
    NUM dy = F(sub)(F(abs)(qy), hy);
    NUM dz = F(sub)(F(abs)(qz), hz);
    NUM outside = F(len3)(F(max)(dx, zero), F(max)(dy, zero), F(max)(dz, zero));
    NUM inside = F(min)(F(max)(dx, F(max)(dy, dz)), zero);
    return F(add)(outside, inside);
}

static NUM F(cylinder)(NUM qx, NUM qy, NUM qz, NUM r, NUM h)
{
    NUM zero = F(cst)(0.0);
    NUM d1 = F(sub)(F(len2)(qx, qy), r);
    NUM d2 = F(sub)(F(abs)(qz), h);
    NUM outside = F(len2)(F(max)(d1, zero), F(max)(d2, zero));
    return F(add)(outside, F(min)(F(max)(d1, d2), zero));
}

static NUM F(plane)(NUM x, NUM y, NUM z, NUM nx, NUM ny, NUM nz, NUM d)
{
    NUM dot = F(add)(F(add)(F(mul)(nx, x), F(mul)(ny, y)), F(mul)(nz, z));
    return F(div)(F(sub)(dot, d), F(len3)(nx, ny, nz));
}

static NUM F(capsule)(NUM x, NUM y, NUM z, const NUM *a)
{
    /* a: ax ay az bx by bz r */
    NUM pax = F(sub)(x, a[0]), pay = F(sub)(y, a[1]), paz = F(sub)(z, a[2]);
    NUM bax = F(sub)(a[3], a[0]), bay = F(sub)(a[4], a[1]), baz = F(sub)(a[5], a[2]);
    NUM num = F(add)(F(add)(F(mul)(pax, bax), F(mul)(pay, bay)), F(mul)(paz, baz));
    NUM den = F(add)(F(add)(F(sqr)(bax), F(sqr)(bay)), F(sqr)(baz));
    NUM h = F(clamp)(F(div)(num, F(max)(den, F(cst)(DBL_MIN))), F(cst)(0.0), F(cst)(1.0));
    NUM l = F(len3)(F(sub)(pax, F(mul)(bax, h)), F(sub)(pay, F(mul)(bay, h)),
                    F(sub)(paz, F(mul)(baz, h)));
    return F(sub)(l, a[6]);
}

static NUM F(gyroid_g)(NUM x, NUM y, NUM z, NUM s)
{
    NUM sx = F(mul)(s, x), sy = F(mul)(s, y), sz = F(mul)(s, z);
    NUM g = F(add)(F(add)(F(mul)(F(sin)(sx), F(cos)(sy)), F(mul)(F(sin)(sy), F(cos)(sz))),
                   F(mul)(F(sin)(sz), F(cos)(sx)));
    return g;
}

/* A primitive (OP_SPHERE1 .. OP_GYROID2) at (x, y, z) with its arguments a
 * (in order; NULL for none). */
static NUM F(prim)(int op, NUM x, NUM y, NUM z, const NUM *a)
{
    switch ((expr_op)op) {
    case OP_SPHERE1:
        return F(sub)(F(len3)(x, y, z), a[0]);
    case OP_SPHERE4:
        return F(sub)(F(len3)(F(sub)(x, a[0]), F(sub)(y, a[1]), F(sub)(z, a[2])), a[3]);
    case OP_ELLIPSOID3:
        return F(ellipsoid)(x, y, z, a[0], a[1], a[2]);
    case OP_ELLIPSOID6:
        return F(ellipsoid)(F(sub)(x, a[0]), F(sub)(y, a[1]), F(sub)(z, a[2]), a[3], a[4], a[5]);
    case OP_TORUS2:
        return F(torus)(x, y, z, a[0], a[1]);
    case OP_TORUS5:
        return F(torus)(F(sub)(x, a[0]), F(sub)(y, a[1]), F(sub)(z, a[2]), a[3], a[4]);
    case OP_BOX3:
        return F(box)(x, y, z, a[0], a[1], a[2]);
    case OP_BOX6:
        return F(box)(F(sub)(x, a[0]), F(sub)(y, a[1]), F(sub)(z, a[2]), a[3], a[4], a[5]);
    case OP_CYLINDER2:
        return F(cylinder)(x, y, z, a[0], a[1]);
    case OP_CYLINDER5:
        return F(cylinder)(F(sub)(x, a[0]), F(sub)(y, a[1]), F(sub)(z, a[2]), a[3], a[4]);
    case OP_PLANE4:
        return F(plane)(x, y, z, a[0], a[1], a[2], a[3]);
    case OP_CAPSULE7:
        return F(capsule)(x, y, z, a);
    case OP_GYROID0:
        return F(gyroid_g)(x, y, z, F(cst)(1.0));
    case OP_GYROID1:
        return F(div)(F(gyroid_g)(x, y, z, a[0]), a[0]);
    case OP_GYROID2:
        return F(sub)(F(div)(F(abs)(F(gyroid_g)(x, y, z, a[0])), a[0]), a[1]);
    default:
        return F(cst)(NAN);
    }
}

/* Run the program. The compiler guarantees a well-formed program whose
 * stack never exceeds GEOM_IMPLICIT_STACK_MAX and ends with one value. */
static NUM F(run)(const expr_ins *code, size_t n, NUM x, NUM y, NUM z, NUM t)
{
    NUM st[GEOM_IMPLICIT_STACK_MAX];
    size_t sp = 0;
    st[0] = F(cst)(NAN);
    for (size_t i = 0; i < n; i++) {
        const expr_ins *in = &code[i];
        NUM *a;
        switch ((expr_op)in->op) {
        case OP_CONST: st[sp++] = F(cst)(in->c); break;
        case OP_X: st[sp++] = x; break;
        case OP_Y: st[sp++] = y; break;
        case OP_Z: st[sp++] = z; break;
        case OP_T: st[sp++] = t; break;
        case OP_ADD: sp--; st[sp - 1] = F(add)(st[sp - 1], st[sp]); break;
        case OP_SUB: sp--; st[sp - 1] = F(sub)(st[sp - 1], st[sp]); break;
        case OP_MUL: sp--; st[sp - 1] = F(mul)(st[sp - 1], st[sp]); break;
        case OP_DIV: sp--; st[sp - 1] = F(div)(st[sp - 1], st[sp]); break;
        case OP_NEG: st[sp - 1] = F(neg)(st[sp - 1]); break;
        case OP_POW: sp--; st[sp - 1] = F(pow)(st[sp - 1], st[sp]); break;
        case OP_POWI: st[sp - 1] = F(powi)(st[sp - 1], in->n); break;
        case OP_SQRT: st[sp - 1] = F(sqrt)(st[sp - 1]); break;
        case OP_ABS: st[sp - 1] = F(abs)(st[sp - 1]); break;
        case OP_SIN: st[sp - 1] = F(sin)(st[sp - 1]); break;
        case OP_COS: st[sp - 1] = F(cos)(st[sp - 1]); break;
        case OP_TAN: st[sp - 1] = F(tan)(st[sp - 1]); break;
        case OP_EXP: st[sp - 1] = F(exp)(st[sp - 1]); break;
        case OP_LOG: st[sp - 1] = F(log)(st[sp - 1]); break;
        case OP_MIN: sp--; st[sp - 1] = F(min)(st[sp - 1], st[sp]); break;
        case OP_MAX: sp--; st[sp - 1] = F(max)(st[sp - 1], st[sp]); break;
        case OP_ATAN2: sp--; st[sp - 1] = F(atan2)(st[sp - 1], st[sp]); break;
        case OP_CLAMP:
            sp -= 2;
            a = &st[sp - 1];
            a[0] = F(clamp)(a[0], a[1], a[2]);
            break;
        case OP_SMIN:
            sp -= 2;
            a = &st[sp - 1];
            a[0] = F(smin)(a[0], a[1], a[2]);
            break;
        case OP_SMAX:
            sp -= 2;
            a = &st[sp - 1];
            a[0] = F(neg)(F(smin)(F(neg)(a[0]), F(neg)(a[1]), a[2]));
            break;
        case OP_SPHERE1: case OP_SPHERE4: case OP_ELLIPSOID3: case OP_ELLIPSOID6:
        case OP_TORUS2: case OP_TORUS5: case OP_BOX3: case OP_BOX6: case OP_CYLINDER2:
        case OP_CYLINDER5: case OP_PLANE4: case OP_CAPSULE7: case OP_GYROID0: case OP_GYROID1:
        case OP_GYROID2: {
            size_t k = (size_t)geom__implicit_op_arity(in->op);
            if (k == 0) {
                st[sp++] = F(prim)(in->op, x, y, z, NULL);
            } else {
                sp -= k - 1;
                st[sp - 1] = F(prim)(in->op, x, y, z, &st[sp - 1]);
            }
            break;
        }
        case OP_COUNT:
            break;
        }
    }
    return st[0];
}
