/* Catmull-Rom (uniform, centripetal, chordal; Barry-Goldman / Yuksel et al.)
 * and Kochanek-Bartels splines, evaluated directly or converted exactly to
 * cubic Bezier segments. */
#include "curve/bspline_basis.h"

geom_status geom_curve_catmull_rom_segments(size_t n, geom_curve_end ends, size_t *nseg)
{
    if (!nseg)
        return GEOM_ERR_INVALID_ARG;
    switch (ends) {
    case GEOM_CURVE_END_EXTRAPOLATE:
        if (n < 2)
            return GEOM_ERR_INVALID_ARG;
        *nseg = n - 1;
        return GEOM_OK;
    case GEOM_CURVE_END_EXCLUDE:
        if (n < 4)
            return GEOM_ERR_INVALID_ARG;
        *nseg = n - 3;
        return GEOM_OK;
    case GEOM_CURVE_END_CLOSED:
        if (n < 3)
            return GEOM_ERR_INVALID_ARG;
        *nseg = n;
        return GEOM_OK;
    }
    return GEOM_ERR_INVALID_ARG;
}

/* Point i of the sequence as the end treatment sees it: i may be -1 or n
 * (reflected phantoms) or wrap (closed). */
static void getp(const double *pts, size_t n, size_t dim, geom_curve_end ends, long i, double *out)
{
    long N = (long)n;
    if (ends == GEOM_CURVE_END_CLOSED) {
        long j = ((i % N) + N) % N;
        memcpy(out, pts + (size_t)j * dim, dim * sizeof(double));
        return;
    }
    if (i < 0) { /* 2 P0 - P1 */
        for (size_t d = 0; d < dim; ++d)
            out[d] = 2.0 * pts[d] - pts[dim + d];
        return;
    }
    if (i >= N) { /* 2 P_{n-1} - P_{n-2} */
        for (size_t d = 0; d < dim; ++d)
            out[d] = 2.0 * pts[(n - 1) * dim + d] - pts[(n - 2) * dim + d];
        return;
    }
    memcpy(out, pts + (size_t)i * dim, dim * sizeof(double));
}

/* Index of the first neighbour (P0 of the 4) of segment s. */
static long seg_first(geom_curve_end ends, size_t s)
{
    return ends == GEOM_CURVE_END_EXCLUDE ? (long)s : (long)s - 1;
}

static double dist(const double *a, const double *b, size_t dim)
{
    return geom_curve_segment_distance(dim, a, a, b); /* scaled: no overflow or underflow */
}

static double knot_step(const double *a, const double *b, size_t dim, double alpha)
{
    if (alpha == 0.0)
        return 1.0;
    double L = dist(a, b, dim);
    if (alpha == 0.5)
        return sqrt(L);
    if (alpha == 1.0)
        return L;
    return pow(L, alpha);
}

geom_status geom_curve_catmull_rom_eval(size_t dim, const double *p0, const double *p1,
                                        const double *p2, const double *p3, double alpha, double s,
                                        double *out)
{
    if (dim < 1 || dim > GEOM_CURVE_MAX_DIM || !p0 || !p1 || !p2 || !p3 || !out)
        return GEOM_ERR_INVALID_ARG;
    if (!isfinite(alpha) || !isfinite(s) || !geom__curve_finite_n(p0, dim) ||
        !geom__curve_finite_n(p1, dim) || !geom__curve_finite_n(p2, dim) ||
        !geom__curve_finite_n(p3, dim))
        return GEOM_ERR_INVALID_ARG;
    if (!(alpha >= 0.0 && alpha <= 1.0))
        return GEOM_ERR_DOMAIN;
    double d0 = knot_step(p0, p1, dim, alpha), d1 = knot_step(p1, p2, dim, alpha),
           d2 = knot_step(p2, p3, dim, alpha);
    if (!(d0 > 0.0 && d1 > 0.0 && d2 > 0.0))
        return GEOM_ERR_DEGENERATE;
    double t0 = 0.0, t1 = d0, t2 = t1 + d1, t3 = t2 + d2;
    double t = t1 + s * d1;
    for (size_t d = 0; d < dim; ++d) {
        double A1 = ((t1 - t) * p0[d] + (t - t0) * p1[d]) / (t1 - t0);
        double A2 = ((t2 - t) * p1[d] + (t - t1) * p2[d]) / (t2 - t1);
        double A3 = ((t3 - t) * p2[d] + (t - t2) * p3[d]) / (t3 - t2);
        double B1 = ((t2 - t) * A1 + (t - t0) * A2) / (t2 - t0);
        double B2 = ((t3 - t) * A2 + (t - t1) * A3) / (t3 - t1);
        out[d] = ((t2 - t) * B1 + (t - t1) * B2) / (t2 - t1);
    }
    return GEOM_OK;
}

static geom_status check_common(size_t dim, size_t n, const double *points, geom_curve_end ends,
                                const double *bezier, size_t *nseg, geom_diag *diag)
{
    if (dim < 1 || dim > GEOM_CURVE_MAX_DIM || !points || !bezier)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: bad dimension or NULL array");
    if (geom_curve_catmull_rom_segments(n, ends, nseg) != GEOM_OK)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: %zu points are too few for this end treatment", n);
    if (!geom__curve_finite_n(points, n * dim))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: a point has a non-finite coordinate");
    return GEOM_OK;
}

geom_status geom_curve_catmull_rom_to_bezier(size_t dim, size_t n, const double *points,
                                             double alpha, geom_curve_end ends, double *bezier,
                                             double *params, geom_diag *diag)
{
    size_t nseg = 0;
    geom_status st = check_common(dim, n, points, ends, bezier, &nseg, diag);
    if (st != GEOM_OK)
        return st;
    if (!isfinite(alpha))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "curve: alpha is not finite");
    if (!(alpha >= 0.0 && alpha <= 1.0))
        return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0, "curve: alpha %g is not in [0, 1]",
                             alpha);
    if (params)
        params[0] = 0.0;
    for (size_t s = 0; s < nseg; ++s) {
        long f = seg_first(ends, s);
        double P[4][GEOM_CURVE_MAX_DIM];
        for (int j = 0; j < 4; ++j)
            getp(points, n, dim, ends, f + j, P[j]);
        double d0 = knot_step(P[0], P[1], dim, alpha), d1 = knot_step(P[1], P[2], dim, alpha),
               d2 = knot_step(P[2], P[3], dim, alpha);
        if (!(d0 > 0.0 && d1 > 0.0 && d2 > 0.0))
            return geom__diag_set(diag, GEOM_ERR_DEGENERATE, NULL, 0, 0,
                                 "curve: consecutive points coincide near segment %zu "
                                 "(alpha > 0 needs distinct neighbours)",
                                 s);
        double *B = bezier + 3 * s * dim;
        for (size_t d = 0; d < dim; ++d) {
            double s0 = (P[1][d] - P[0][d]) / d0, s1 = (P[2][d] - P[1][d]) / d1,
                   s2 = (P[3][d] - P[2][d]) / d2;
            /* tangents (w.r.t. the CR parameter) as weighted slope averages,
             * scaled to the segment's parameter length d1 */
            double m1 = (d1 * s0 + d0 * s1) / (d0 + d1);
            double m2 = (d2 * s1 + d1 * s2) / (d1 + d2);
            B[d] = P[1][d];
            B[dim + d] = P[1][d] + d1 * m1 / 3.0;
            B[2 * dim + d] = P[2][d] - d1 * m2 / 3.0;
            B[3 * dim + d] = P[2][d];
        }
        if (params)
            params[s + 1] = params[s] + d1;
    }
    return GEOM_OK;
}

geom_status geom_curve_kochanek_bartels_to_bezier(size_t dim, size_t n, const double *points,
                                                  const geom_kb_params *tcb, size_t ntcb,
                                                  geom_curve_end ends, double *bezier,
                                                  geom_diag *diag)
{
    size_t nseg = 0;
    geom_status st = check_common(dim, n, points, ends, bezier, &nseg, diag);
    if (st != GEOM_OK)
        return st;
    if (!(ntcb == 0 || ntcb == 1 || ntcb == n) || (ntcb > 0 && !tcb))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: %zu tension/continuity/bias entries for %zu points", ntcb, n);
    for (size_t i = 0; i < ntcb; ++i)
        if (!isfinite(tcb[i].tension) || !isfinite(tcb[i].continuity) || !isfinite(tcb[i].bias))
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "curve: tension/continuity/bias %zu not finite", i);
    for (size_t s = 0; s < nseg; ++s) {
        long f = seg_first(ends, s);
        double P[4][GEOM_CURVE_MAX_DIM];
        for (int j = 0; j < 4; ++j)
            getp(points, n, dim, ends, f + j, P[j]);
        /* the key indices of the segment's two end points */
        long N = (long)n;
        size_t i1 = (size_t)(((f + 1) % N + N) % N), i2 = (size_t)(((f + 2) % N + N) % N);
        geom_kb_params k1 = {0, 0, 0}, k2 = {0, 0, 0};
        if (ntcb == 1)
            k1 = k2 = tcb[0];
        else if (ntcb == n) {
            k1 = tcb[i1];
            k2 = tcb[i2];
        }
        double *B = bezier + 3 * s * dim;
        for (size_t d = 0; d < dim; ++d) {
            double a1 = P[1][d] - P[0][d], b1 = P[2][d] - P[1][d]; /* around P1 */
            double a2 = P[2][d] - P[1][d], b2 = P[3][d] - P[2][d]; /* around P2 */
            double t1 = 1.0 - k1.tension, t2 = 1.0 - k2.tension;
            double out1 = 0.5 * t1 *
                          ((1.0 + k1.bias) * (1.0 + k1.continuity) * a1 +
                           (1.0 - k1.bias) * (1.0 - k1.continuity) * b1);
            double in2 = 0.5 * t2 *
                         ((1.0 + k2.bias) * (1.0 - k2.continuity) * a2 +
                          (1.0 - k2.bias) * (1.0 + k2.continuity) * b2);
            B[d] = P[1][d];
            B[dim + d] = P[1][d] + out1 / 3.0;
            B[2 * dim + d] = P[2][d] - in2 / 3.0;
            B[3 * dim + d] = P[2][d];
        }
    }
    return GEOM_OK;
}
