/* Degree elevation (The NURBS Book A5.9). */
#include "curve/bspline_basis.h"

/* Largest degree an elevation may reach: past about 1020 the binomial
 * coefficients of A5.9 overflow a double (NaN control points), and the work
 * grows with the square of the degree. */
#define ELEVATE_MAX_DEGREE 1000L

static int is_clamped(const geom_nurbs_curve *c)
{
    size_t p = (size_t)c->degree, n = c->n;
    return c->knots[0] == c->knots[p] && c->knots[n] == c->knots[n + p];
}

geom_status geom_curve_nurbs_elevate_bound(const geom_nurbs_curve *c, int times, size_t *n,
                                           size_t *nknots)
{
    if (geom__curve_check_cheap(c) != GEOM_OK || times < 0)
        return GEOM_ERR_INVALID_ARG;
    if ((long)c->degree + (long)times > ELEVATE_MAX_DEGREE)
        return GEOM_ERR_LIMIT;
    size_t p = (size_t)c->degree, s = 0;
    const double *U = c->knots;
    for (size_t i = p + 1; i < c->n; ++i)
        if (U[i] != U[i - 1] && U[i] > U[p] && U[i] < U[c->n])
            ++s;
    size_t nn = c->n + (size_t)times * (s + 1);
    if (n)
        *n = nn;
    if (nknots)
        *nknots = nn + p + (size_t)times + 1;
    return GEOM_OK;
}

geom_status geom_curve_nurbs_elevate(const geom_nurbs_curve *c, int times, double *knots,
                                     double *points, double *weights, geom_nurbs_curve *out,
                                     geom_diag *diag)
{
    geom_status st = geom__curve_check_knot_op(c, knots, points, weights, out, diag);
    if (st != GEOM_OK)
        return st;
    if (times < 0)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "curve: negative elevation %d",
                             times);
    if ((long)c->degree + (long)times > ELEVATE_MAX_DEGREE)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0,
                             "curve: elevating degree %d by %d goes past degree %ld", c->degree,
                             times, ELEVATE_MAX_DEGREE);
    if (!is_clamped(c))
        return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                             "curve: degree elevation needs a clamped knot vector "
                             "(use geom_curve_nurbs_clamp first)");
    size_t D = geom__curve_hdim(c);
    geom__curve_hbuf hb = {points, c->weights ? weights : NULL, c->dim};
    const double *U = c->knots;
    long p = c->degree, t = times, ph = p + t, ph2 = ph / 2;
    long n = (long)c->n - 1, m = n + p + 1;
    if (t == 0) {
        memcpy(knots, U, (size_t)(m + 1) * sizeof(double));
        memcpy(points, c->points, c->n * c->dim * sizeof(double));
        if (c->weights)
            memcpy(weights, c->weights, c->n * sizeof(double));
        *out = *c;
        out->knots = knots;
        out->points = points;
        out->weights = hb.w;
        return GEOM_OK;
    }
    size_t P1 = (size_t)p + 1, PH1 = (size_t)ph + 1;
    size_t need = PH1 * P1 + (P1 + PH1 + P1) * D + P1;
    geom__scratch sc;
    st = geom__scratch_init(&sc, need);
    if (st != GEOM_OK) {
        geom__scratch_free(&sc);
        return geom__diag_set(diag, st, NULL, 0, 0, "curve: out of memory");
    }
    double *bezalfs = sc.mem;          /* (ph+1) x (p+1) */
    double *bpts = bezalfs + PH1 * P1; /* p+1 points */
    double *ebpts = bpts + P1 * D;     /* ph+1 points */
    double *nextb = ebpts + PH1 * D;   /* p+1 points (p-1 used) */
    double *alfs = nextb + P1 * D;     /* p+1 (p-1 used) */
#define BZ(i, j) bezalfs[(size_t)(i)*P1 + (size_t)(j)]
#define BP(i) (bpts + (size_t)(i)*D)
#define EB(i) (ebpts + (size_t)(i)*D)
#define NB(i) (nextb + (size_t)(i)*D)
    for (size_t i = 0; i < PH1 * P1; ++i)
        bezalfs[i] = 0.0;
    BZ(0, 0) = 1.0;
    BZ(ph, p) = 1.0;
    for (long i = 1; i <= ph2; ++i) {
        double inv = 1.0 / geom__binom(ph, i);
        long mpi = p < i ? p : i;
        for (long j = (i - t > 0 ? i - t : 0); j <= mpi; ++j)
            BZ(i, j) = inv * geom__binom(p, j) * geom__binom(t, i - j);
    }
    for (long i = ph2 + 1; i <= ph - 1; ++i) {
        long mpi = p < i ? p : i;
        for (long j = (i - t > 0 ? i - t : 0); j <= mpi; ++j)
            BZ(i, j) = BZ(ph - i, p - j);
    }
    double *Uh = knots;
    double h[GEOM_CURVE_HDIM_MAX], g[GEOM_CURVE_HDIM_MAX];
    long mh = ph, kind = ph + 1, r = -1, a = p, b = p + 1, cind = 1;
    double ua = U[0];
    geom__curve_hget(c, 0, h);
    geom__curve_hbuf_set(&hb, 0, h);
    for (long i = 0; i <= ph; ++i)
        Uh[i] = ua;
    for (long i = 0; i <= p; ++i)
        geom__curve_hget(c, (size_t)i, BP(i));
    while (b < m) {
        long i = b;
        while (b < m && U[b] == U[b + 1])
            ++b;
        long mul = b - i + 1;
        mh = mh + mul + t;
        double ub = U[b];
        long oldr = r;
        r = p - mul;
        /* oldr < 0 after the first segment (a != p): the previous knot had
         * multiplicity p+1 (a jump), so the new segment's first point is not
         * shared with the previous one (the book assumes multiplicity <= p) */
        long lbz = oldr > 0 ? (oldr + 2) / 2 : ((oldr < 0 && a != p) ? 0 : 1);
        long rbz = r > 0 ? ph - (r + 1) / 2 : ph;
        if (r > 0) {
            double numer = ub - ua;
            for (long k = p; k > mul; --k)
                alfs[k - mul - 1] = numer / (U[a + k] - ua);
            for (long j = 1; j <= r; ++j) {
                long save = r - j, s = mul + j;
                for (long k = p; k >= s; --k)
                    geom__curve_hcomb(D, BP(k), alfs[k - s], BP(k), 1.0 - alfs[k - s], BP(k - 1));
                memcpy(NB(save), BP(p), D * sizeof(double));
            }
        }
        for (long ii = lbz; ii <= ph; ++ii) {
            for (size_t d = 0; d < D; ++d)
                EB(ii)[d] = 0.0;
            long mpi = p < ii ? p : ii;
            for (long j = (ii - t > 0 ? ii - t : 0); j <= mpi; ++j)
                for (size_t d = 0; d < D; ++d)
                    EB(ii)[d] += BZ(ii, j) * BP(j)[d];
        }
        if (oldr > 1) {
            long first = kind - 2, last = kind;
            double den = ub - ua;
            double bet = (ub - Uh[kind - 1]) / den;
            for (long tr = 1; tr < oldr; ++tr) {
                long ii = first, j = last, kj = j - kind + 1;
                while (j - ii > tr) {
                    if (ii < cind) {
                        double alf = (ub - Uh[ii]) / (ua - Uh[ii]);
                        geom__curve_hbuf_get(&hb, (size_t)ii, h);
                        geom__curve_hbuf_get(&hb, (size_t)(ii - 1), g);
                        geom__curve_hcomb(D, h, alf, h, 1.0 - alf, g);
                        geom__curve_hbuf_set(&hb, (size_t)ii, h);
                    }
                    if (j >= lbz) {
                        if (j - tr <= kind - ph + oldr) {
                            double gam = (ub - Uh[j - tr]) / den;
                            geom__curve_hcomb(D, EB(kj), gam, EB(kj), 1.0 - gam, EB(kj + 1));
                        } else {
                            geom__curve_hcomb(D, EB(kj), bet, EB(kj), 1.0 - bet, EB(kj + 1));
                        }
                    }
                    ++ii;
                    --j;
                    --kj;
                }
                --first;
                ++last;
            }
        }
        if (a != p)
            for (long ii = 0; ii < ph - oldr; ++ii)
                Uh[kind++] = ua;
        for (long j = lbz; j <= rbz; ++j)
            geom__curve_hbuf_set(&hb, (size_t)cind++, EB(j));
        if (b < m) {
            for (long j = 0; j < r; ++j)
                memcpy(BP(j), NB(j), D * sizeof(double));
            for (long j = (r > 0 ? r : 0); j <= p; ++j)
                geom__curve_hget(c, (size_t)(b - p + j), BP(j));
            a = b;
            ++b;
            ua = ub;
        } else {
            for (long ii = 0; ii <= ph; ++ii)
                Uh[kind + ii] = ub;
        }
    }
#undef BZ
#undef BP
#undef EB
#undef NB
    geom__scratch_free(&sc);
    size_t nh = (size_t)(mh - ph); /* number of control points */
    geom__curve_hbuf_result(&hb, (int)ph, nh, knots, out);
    return GEOM_OK;
}
