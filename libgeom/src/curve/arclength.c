/* Arc length by adaptive Gauss-Legendre quadrature over knot spans. */
#include "curve/bspline_basis.h"

#include <float.h>

/* 8-point Gauss-Legendre rule on [-1, 1] (nodes +-x, weights w). */
static const double GL_X[4] = {0.18343464249564980494, 0.52553240991632898582,
                               0.79666647741362673959, 0.96028985649753623168};
static const double GL_W[4] = {0.36268378337836198297, 0.31370664587788728734,
                               0.22238103445337447054, 0.10122853629037625915};

#define ARC_MAX_DEPTH 50
/* Evaluation budget: beyond it intervals are accepted as they are (and the
 * result is flagged GEOM_ERR_LIMIT). Noisy speeds (e.g. coordinates far
 * from the origin) would otherwise make the refinement run away. */
#define ARC_MAX_EVALS ((size_t)1 << 21)

typedef struct arc_ctx {
    const geom_nurbs_curve *c;
    size_t k;
    double *ders;
    double *work;
    size_t evals;
    double err_sum;
    size_t intervals;
    int hit_limit;
} arc_ctx;

static double speed(arc_ctx *x, double u)
{
    geom__curve_span_derivs(x->c, x->k, u, 1, x->ders, x->work);
    ++x->evals;
    const double *d1 = x->ders + x->c->dim;
    double s = 0.0;
    for (size_t d = 0; d < x->c->dim; ++d)
        s += d1[d] * d1[d];
    return sqrt(s);
}

static double gl8(arc_ctx *x, double a, double b)
{
    double m = 0.5 * (a + b), h = 0.5 * (b - a), s = 0.0;
    for (int i = 0; i < 4; ++i)
        s += GL_W[i] * (speed(x, m - h * GL_X[i]) + speed(x, m + h * GL_X[i]));
    return s * h;
}

/* Integral over [a, b] given the one-interval value `whole`. */
static double adapt(arc_ctx *x, double a, double b, double whole, double tol, int depth)
{
    double m = 0.5 * (a + b);
    double l = gl8(x, a, m), r = gl8(x, m, b);
    double err = fabs(l + r - whole);
    /* below the rounding noise of the two sums there is nothing to gain */
    double noise = 64.0 * DBL_EPSILON * (fabs(l) + fabs(r));
    if (err <= tol || err <= noise || depth >= ARC_MAX_DEPTH || !(m > a && m < b) ||
        x->evals >= ARC_MAX_EVALS) {
        if (err > tol && err > noise)
            x->hit_limit = 1;
        x->err_sum += err;
        x->intervals += 1;
        return l + r;
    }
    return adapt(x, a, m, l, 0.5 * tol, depth + 1) + adapt(x, m, b, r, 0.5 * tol, depth + 1);
}

geom_status geom_curve_nurbs_arc_length(const geom_nurbs_curve *c, double u0, double u1,
                                        double rel_tol, double *length, geom_error_report *report,
                                        geom_diag *diag)
{
    geom_status st = geom__curve_check(c, diag);
    if (st != GEOM_OK)
        return st;
    if (!length || !isfinite(u0) || !isfinite(u1) || !isfinite(rel_tol) || rel_tol < 0.0)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: bad arc length arguments (NULL output or NaN/Inf)");
    const double *U = c->knots;
    size_t p = (size_t)c->degree;
    if (!(u0 >= U[p] && u1 <= U[c->n] && u0 <= u1))
        return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                             "curve: [%.17g, %.17g] is not an interval of the domain", u0, u1);
    if (rel_tol == 0.0)
        rel_tol = 1e-13;
    if (rel_tol < 1e-15)
        rel_tol = 1e-15;
    size_t nd1 = 2;
    geom__scratch sc;
    st = geom__scratch_init(&sc, nd1 * c->dim + geom__curve_span_derivs_work(c, 1));
    if (st != GEOM_OK) {
        geom__scratch_free(&sc);
        return geom__diag_set(diag, st, NULL, 0, 0, "curve: out of memory");
    }
    arc_ctx x = {c, 0, sc.mem, sc.mem + nd1 * c->dim, 0, 0.0, 0, 0};
    /* first pass: one rule per span piece, for the tolerance's scale */
    double total0 = 0.0;
    for (size_t k = p; k < c->n; ++k) {
        double a = fmax(U[k], u0), b = fmin(U[k + 1], u1);
        if (!(U[k] < U[k + 1]) || !(a < b))
            continue;
        x.k = k;
        total0 += gl8(&x, a, b);
    }
    double abs_tol = rel_tol * total0, width = u1 - u0, total = 0.0;
    for (size_t k = p; k < c->n; ++k) {
        double a = fmax(U[k], u0), b = fmin(U[k + 1], u1);
        if (!(U[k] < U[k + 1]) || !(a < b))
            continue;
        x.k = k;
        double whole = gl8(&x, a, b);
        total += adapt(&x, a, b, whole, abs_tol * ((b - a) / width), 0);
    }
    geom__scratch_free(&sc);
    *length = total;
    if (report) {
        report->max_error = x.err_sum;
        report->mean_error = x.intervals ? x.err_sum / (double)x.intervals : 0.0;
        report->method = x.intervals ? GEOM_ERROR_ESTIMATE : GEOM_ERROR_NONE;
        report->evaluations = x.evals;
    }
    if (x.hit_limit)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0,
                             "curve: arc length did not reach the tolerance in %d levels",
                             ARC_MAX_DEPTH);
    return GEOM_OK;
}
