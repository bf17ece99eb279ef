/*
 * Generalized winding number (Jacobson, Kavan and Sorkine-Hornung, "Robust
 * inside-outside segmentation using generalized winding numbers", 2013) as
 * the sum of signed solid angles (Van Oosterom and Strackee 1983), with the
 * fast hierarchical evaluation of Barill, Dickson, Schmidt, Levin and
 * Jacobson, "Fast winding numbers for soups and clouds", 2018: a BVH node
 * whose centre is farther than beta times its radius is replaced by its
 * first-order dipole term (p - q).N / (4 pi |p - q|^3). The truncation error
 * of that term is bounded by the Taylor remainder of the kernel: with A the
 * node's triangle area, r its radius and R the distance to its centre,
 * |error| <= A r sup|Hess(1/(4 pi |y|))| = A r 2 / (4 pi (R - r)^3).
 * By default a node is approximated by Barill et al.'s criterion alone
 * (R > beta r) and the report carries the sum of the accepted terms, a
 * rigorous but pessimistic bound. With a tolerance, a node is approximated
 * only when its term is at most tolerance * A / (total area): the accepted
 * nodes are disjoint, so a query's error is then at most `tolerance`.
 * For the signed distance, a query whose bound straddles 1/2 is evaluated
 * again with tightened terms (1/4, then 1/32 of the area share) and finally
 * exactly, until the side of 1/2 is certain.
 */
#include "spatial/spatial_internal.h"

#include <string.h>

#define FOUR_PI (4.0 * GEOM_PI)

double geom__solid_angle(const double q[3], const double A[3], const double B[3], const double C[3])
{
    double a[3] = {A[0] - q[0], A[1] - q[1], A[2] - q[2]};
    double b[3] = {B[0] - q[0], B[1] - q[1], B[2] - q[2]};
    double c[3] = {C[0] - q[0], C[1] - q[1], C[2] - q[2]};
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                 a[2] * (b[0] * c[1] - b[1] * c[0]);
    double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
    double ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
    double den = la * lb * lc + ab * lc + bc * la + ca * lb;
    return 2.0 * atan2(det, den);
}

/* Winding number at q; *err receives the bound, *work the term count. */
static double winding_one(const geom_meshdist *m, const double q[3], double beta,
                          double tol_per_area, double *err, size_t *work)
{
    size_t nn;
    const geom_bvh_node *nodes = geom_bvh_nodes(m->bvh, &nn);
    double sum = 0, e = 0;
    size_t wk = 0;
    if (nn) {
        uint32_t stack[256];
        int sp = 0;
        stack[sp++] = 0;
        while (sp > 0) {
            uint32_t i = stack[--sp];
            const geom_bvh_node *nd = &nodes[i];
            const geom__dipole *d = &m->dip[i];
            if (beta > 0) {
                double v[3] = {d->c[0] - q[0], d->c[1] - q[1], d->c[2] - q[2]};
                double R = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                if (R > beta * d->r && R > d->r) {
                    double g = R - d->r;
                    double term = d->area * d->r * 2.0 / (FOUR_PI * g * g * g);
                    if (tol_per_area <= 0 || term <= tol_per_area * d->area) {
                        sum += (v[0] * d->n[0] + v[1] * d->n[1] + v[2] * d->n[2]) /
                               (FOUR_PI * R * R * R);
                        e += term;
                        wk++;
                        continue;
                    }
                }
            }
            if (nd->count) {
                const double *tv = m->tv + 9 * (size_t)nd->index;
                for (uint32_t k = 0; k < nd->count; k++, tv += 9)
                    sum += geom__solid_angle(q, tv, tv + 3, tv + 6) / FOUR_PI;
                wk += nd->count;
                continue;
            }
            stack[sp++] = nd->index;
            stack[sp++] = i + 1;
        }
    }
    /* Rounding of the sum: a few ulp per term of magnitude <= 1/2. */
    e += (double)wk * 4.0 * 0x1p-53;
    *err = e;
    *work = wk;
    return sum;
}

static geom_status run(const geom_meshdist *m, const double *queries, size_t nq, double *out,
                       int sd, geom_error_report *report, int threads, geom_diag *diag)
{
    if (!m || !out || (nq && !queries))
        return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "winding number: NULL argument");
    size_t bad = geom__first_nonfinite(queries, nq, 3);
    if (bad < nq)
        return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "winding number: query %zu has a NaN/Inf coordinate", bad);
    double emax = 0, esum = 0;
    size_t work = 0;
    ptrdiff_t n = (ptrdiff_t)nq;
    int nth = geom__spatial_threads(threads);
    (void)nth;
    /* Per-query errors go to out-of-band storage so the reduction is in
     * query order (max and sum are then thread-count independent). */
    double *errs = report ? geom_alloc(m->has_alloc ? &m->alloc : NULL, (nq ? nq : 1) * sizeof *errs) : NULL;
    size_t *works = report ? geom_alloc(m->has_alloc ? &m->alloc : NULL, (nq ? nq : 1) * sizeof *works) : NULL;
    if (report && (!errs || !works)) {
        geom_free(m->has_alloc ? &m->alloc : NULL, errs, (nq ? nq : 1) * sizeof *errs);
        geom_free(m->has_alloc ? &m->alloc : NULL, works, (nq ? nq : 1) * sizeof *works);
        return geom_diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "winding number: out of memory");
    }
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp parallel for schedule(dynamic, 64) num_threads(nth) if (nq > 64)
#endif
    for (ptrdiff_t i = 0; i < n; i++) {
        const double *q = queries + 3 * i;
        double e;
        size_t wk;
        double tpa = m->tolerance > 0 && m->area_total > 0 ? m->tolerance / m->area_total : 0.0;
        double w = winding_one(m, q, m->beta, tpa, &e, &wk);
        if (sd && m->beta > 0 && !(fabs(w - 0.5) > e)) {
            /* The bound straddles 1/2: tighten it (approximate only nodes
             * whose error terms fit in 1/4, then 1/32 of their area share),
             * then the exact sum, until the side of 1/2 is certain. */
            static const double tight[2] = {0.25, 0.03125};
            for (int pass = 0; pass < 3 && !(fabs(w - 0.5) > e); pass++) {
                size_t wk2;
                if (pass < 2 && m->area_total > 0) {
                    w = winding_one(m, q, m->beta, tight[pass] / m->area_total, &e, &wk2);
                } else {
                    w = winding_one(m, q, -1.0, 0.0, &e, &wk2);
                    e = 0;
                    pass = 2;
                }
                wk += wk2;
            }
        }
        if (sd) {
            double d = sqrt(geom__meshdist_closest_d2(m, q));
            out[i] = w >= 0.5 ? -d : d;
        } else {
            out[i] = w;
        }
        if (errs) {
            errs[i] = m->beta > 0 ? e : 0.0;
            works[i] = wk;
        }
    }
    if (report) {
        for (size_t i = 0; i < nq; i++) {
            if (errs[i] > emax)
                emax = errs[i];
            esum += errs[i];
            work += works[i];
        }
        report->max_error = emax;
        report->mean_error = nq ? esum / (double)nq : 0.0;
        report->method = GEOM_ERROR_BOUND;
        report->evaluations = work;
        geom_free(m->has_alloc ? &m->alloc : NULL, errs, (nq ? nq : 1) * sizeof *errs);
        geom_free(m->has_alloc ? &m->alloc : NULL, works, (nq ? nq : 1) * sizeof *works);
    }
    return GEOM_OK;
}

geom_status geom_meshdist_winding(const geom_meshdist *m, const double *queries, size_t nq, double *w,
                                  geom_error_report *report, int threads, geom_diag *diag)
{
    return run(m, queries, nq, w, 0, report, threads, diag);
}

geom_status geom_meshdist_signed_distance(const geom_meshdist *m, const double *queries, size_t nq,
                                          double *sd, geom_error_report *report, int threads,
                                          geom_diag *diag)
{
    return run(m, queries, nq, sd, 1, report, threads, diag);
}
