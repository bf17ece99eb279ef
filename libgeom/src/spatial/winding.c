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
 * |error| <= A r sup|Hess(1/(4 pi |y|))| = A r 2 / (4 pi (R - r)^3), and a
 * second bound that is small on flat patches (side_term below) is used when
 * it is smaller; R - r may be replaced by the distance to the node's box.
 * By default a node is approximated by Barill et al.'s criterion alone
 * (R > beta r) and the report carries the sum of the accepted terms, a
 * rigorous but pessimistic bound. With a tolerance, a node is approximated
 * only when its term is at most tolerance * A / (total area): the accepted
 * nodes are disjoint, so a query's error is then at most `tolerance`.
 * For the signed distance only the side of 1/2 matters, so the bound is
 * driven down adaptively: the approximated nodes are kept in a max-heap on
 * their error terms, and while the bound straddles 1/2 the node with the
 * largest term is opened (its dipole replaced by its children's terms, or by
 * its exact triangles for a leaf). Each term there uses the larger of two
 * lower bounds of the distance from q to the node's surface, R - r and the
 * distance to the node's box (the Taylor segment from the centre to any
 * surface point stays inside both the ball and the box). A query whose bound
 * still straddles 1/2 once every node is open is decided by the exact sum in
 * the order of the plain evaluation, so the sign is always that of the exact
 * solid-angle sum.
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

/* Error bound of a node's dipole term, g a lower bound of the distance from
 * q to the node's surface (and to the segments from its centre to it). The
 * smaller of two bounds: the first-order one, A r 2 / (4 pi g^3), and one
 * that sees flat patches. With nu the mean normal direction, split each
 * triangle's unit normal into nu + (n_t - nu): the second part is bounded
 * as before with sum A_t |n_t - nu| (dev) in place of A; for the first, the
 * gradient of the kernel expanded to first order about c leaves the moment
 * integral of (x - c) (zero up to rounding: c is the area centroid; m1) and
 * a remainder at most 1/2 sup|D^3 G| |x - c|^2 with sup|D^3 G| = 6 / (4 pi
 * g^4) (Legendre: |d^k/du^k 1/|y|| <= k! / |y|^(k+1)), integrated: i2. */
static double side_term(const geom__dipole *d, double g)
{
    double g3 = FOUR_PI * g * g * g;
    double first = d->area * d->r * 2.0 / g3;
    double flat = (2.0 * d->r * d->dev + 2.0 * d->m1) / g3 + 3.0 * d->i2 / (g3 * g);
    return (first < flat ? first : flat) * (1.0 + 0x1p-40);
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
                    double gb = sqrt(geom__box_d2(&nd->box, q)) * (1.0 - 0x1p-40);
                    if (gb > g)
                        g = gb;
                    double term = side_term(d, g);
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

/* ---- signed distance: refine the approximation until the side of 1/2 is
 * certain (see the comment at the top). */

typedef struct heap_item {
    double term; /* error bound of the node's dipole term */
    double val;  /* the dipole term added to the sum */
    uint32_t node;
    uint32_t pad;
} heap_item;

typedef struct side_state {
    const geom_meshdist *m;
    const geom_bvh_node *nodes;
    const double *q;
    heap_item *h;
    size_t n, cap;
    int on_heap; /* h is allocated (not the stack buffer) */
    double sum, err, abs_sum, err_peak;
    size_t ops, exact;
} side_state;

static int heap_push(side_state *s, double term, double val, uint32_t node)
{
    if (s->n == s->cap) {
        const geom_allocator *a = s->m->has_alloc ? &s->m->alloc : NULL;
        size_t nc = 2 * s->cap;
        heap_item *p = geom__alloc(a, nc * sizeof *p);
        if (!p)
            return -1;
        memcpy(p, s->h, s->n * sizeof *p);
        if (s->on_heap)
            geom__free(a, s->h, s->cap * sizeof *p);
        s->h = p;
        s->cap = nc;
        s->on_heap = 1;
    }
    size_t i = s->n++;
    while (i > 0) {
        size_t up = (i - 1) / 2;
        if (!(s->h[up].term < term))
            break;
        s->h[i] = s->h[up];
        i = up;
    }
    s->h[i] = (heap_item){term, val, node, 0};
    return 0;
}

static heap_item heap_pop(side_state *s)
{
    heap_item top = s->h[0], last = s->h[--s->n];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= s->n)
            break;
        if (c + 1 < s->n && s->h[c + 1].term > s->h[c].term)
            c++;
        if (!(s->h[c].term > last.term))
            break;
        s->h[i] = s->h[c];
        i = c;
    }
    if (s->n)
        s->h[i] = last;
    return top;
}

/* Add the subtree of node i: Barill's criterion picks the dipoles (pushed
 * with their error terms), the rest is summed exactly. */
static int side_add(side_state *s, uint32_t root)
{
    const geom_meshdist *m = s->m;
    const double *q = s->q;
    uint32_t stack[256];
    int sp = 0;
    stack[sp++] = root;
    while (sp > 0) {
        uint32_t i = stack[--sp];
        const geom_bvh_node *nd = &s->nodes[i];
        const geom__dipole *d = &m->dip[i];
        double v[3] = {d->c[0] - q[0], d->c[1] - q[1], d->c[2] - q[2]};
        double R = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (R > m->beta * d->r && R > d->r) {
            double g = R - d->r;
            double gb = sqrt(geom__box_d2(&nd->box, q)) * (1.0 - 0x1p-40);
            if (gb > g)
                g = gb;
            double term = side_term(d, g);
            double val = (v[0] * d->n[0] + v[1] * d->n[1] + v[2] * d->n[2]) / (FOUR_PI * R * R * R);
            if (heap_push(s, term, val, i) < 0)
                return -1;
            s->sum += val;
            s->abs_sum += fabs(val);
            s->err += term;
            if (s->err > s->err_peak)
                s->err_peak = s->err;
            s->ops++;
            continue;
        }
        if (nd->count) {
            const double *tv = m->tv + 9 * (size_t)nd->index;
            for (uint32_t k = 0; k < nd->count; k++, tv += 9) {
                double t = geom__solid_angle(q, tv, tv + 3, tv + 6) / FOUR_PI;
                s->sum += t;
                s->abs_sum += fabs(t);
            }
            s->exact += nd->count;
            s->ops += nd->count;
            continue;
        }
        stack[sp++] = nd->index;
        stack[sp++] = i + 1;
    }
    return 0;
}

/* Bound on |computed sum - exact sum|: the accepted terms, a few ulp per
 * exact term and per dipole term, and the summation (n ops of magnitude at
 * most abs_sum each, plus the running bound's own rounding). */
static double side_bound(const side_state *s)
{
    double ops = (double)s->ops;
    return s->err + (4.0 * (double)s->exact + 16.0 * s->abs_sum + ops * s->abs_sum +
                     ops * s->err_peak) * 0x1p-53;
}

/* 1 inside (w >= 1/2), 0 outside, 2 undecided after full refinement, -1 out
 * of memory. */
static int sd_side(const geom_meshdist *m, const double q[3], double *err, size_t *work)
{
    heap_item buf[512];
    side_state s;
    memset(&s, 0, sizeof s);
    s.m = m;
    s.nodes = geom_bvh_nodes(m->bvh, NULL);
    s.q = q;
    s.h = buf;
    s.cap = sizeof buf / sizeof *buf;
    int res = 2;
    if (m->nt == 0) {
        res = 0;
    } else if (side_add(&s, 0) < 0) {
        res = -1;
    } else {
        for (;;) {
            double b = side_bound(&s);
            if (fabs(s.sum - 0.5) > b) {
                res = s.sum > 0.5;
                break;
            }
            if (s.n == 0)
                break;
            heap_item it = heap_pop(&s);
            s.sum -= it.val;
            s.abs_sum += fabs(it.val);
            s.err -= it.term;
            s.ops++;
            const geom_bvh_node *nd = &s.nodes[it.node];
            if (nd->count) {
                const double *tv = m->tv + 9 * (size_t)nd->index;
                for (uint32_t k = 0; k < nd->count; k++, tv += 9) {
                    double t = geom__solid_angle(q, tv, tv + 3, tv + 6) / FOUR_PI;
                    s.sum += t;
                    s.abs_sum += fabs(t);
                }
                s.exact += nd->count;
                s.ops += nd->count;
            } else if (side_add(&s, it.node + 1) < 0 || side_add(&s, nd->index) < 0) {
                res = -1;
                break;
            }
        }
    }
    *err = side_bound(&s);
    *work = s.ops;
    if (s.on_heap)
        geom__free(m->has_alloc ? &m->alloc : NULL, s.h, s.cap * sizeof *s.h);
    return res;
}

static geom_status run(const geom_meshdist *m, const double *queries, size_t nq, double *out,
                       int sd, geom_error_report *report, int threads, geom_diag *diag)
{
    if (!m || !out || (nq && !queries))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "winding number: NULL argument");
    size_t bad = geom__first_nonfinite(queries, nq, 3);
    if (bad < nq)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "winding number: query %zu has a NaN/Inf coordinate", bad);
    /* Signed distance: the distances first, through the batch closest-point
     * query (Morton-ordered); the signs are applied below. */
    if (sd) {
        geom_status st = geom_meshdist_closest(m, queries, nq, NULL, NULL, NULL, out, threads, diag);
        if (st != GEOM_OK)
            return st;
    }
    double emax = 0, esum = 0;
    size_t work = 0;
    ptrdiff_t n = (ptrdiff_t)nq;
    int nomem = 0;
    int nth = geom__spatial_threads(threads);
    (void)nth;
    /* Per-query errors go to out-of-band storage so the reduction is in
     * query order (max and sum are then thread-count independent). */
    double *errs = report ? geom__alloc(m->has_alloc ? &m->alloc : NULL, (nq ? nq : 1) * sizeof *errs) : NULL;
    size_t *works = report ? geom__alloc(m->has_alloc ? &m->alloc : NULL, (nq ? nq : 1) * sizeof *works) : NULL;
    if (report && (!errs || !works)) {
        geom__free(m->has_alloc ? &m->alloc : NULL, errs, (nq ? nq : 1) * sizeof *errs);
        geom__free(m->has_alloc ? &m->alloc : NULL, works, (nq ? nq : 1) * sizeof *works);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "winding number: out of memory");
    }
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp parallel for schedule(dynamic, 64) num_threads(nth) if (nq > 64)
#endif
    for (ptrdiff_t i = 0; i < n; i++) {
        const double *q = queries + 3 * i;
        double e;
        size_t wk;
        double tpa = m->tolerance > 0 && m->area_total > 0 ? m->tolerance / m->area_total : 0.0;
        double w;
        if (sd && m->beta > 0) {
            int side = sd_side(m, q, &e, &wk);
            if (side < 0) {
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp atomic write
#endif
                nomem = 1;
                side = 0;
            } else if (side == 2) {
                /* Undecided at full refinement: the exact sum as evaluated
                 * without approximation. */
                size_t wk2;
                double ex = winding_one(m, q, -1.0, 0.0, &e, &wk2);
                wk += wk2;
                e = 0;
                side = ex >= 0.5;
            }
            w = side ? 1.0 : 0.0;
        } else {
            w = winding_one(m, q, m->beta, tpa, &e, &wk);
        }
        if (sd) {
            out[i] = w >= 0.5 ? -out[i] : out[i];
        } else {
            out[i] = w;
        }
        if (errs) {
            errs[i] = m->beta > 0 ? e : 0.0;
            works[i] = wk;
        }
    }
    if (nomem) {
        if (report) {
            geom__free(m->has_alloc ? &m->alloc : NULL, errs, (nq ? nq : 1) * sizeof *errs);
            geom__free(m->has_alloc ? &m->alloc : NULL, works, (nq ? nq : 1) * sizeof *works);
        }
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "signed distance: out of memory");
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
        geom__free(m->has_alloc ? &m->alloc : NULL, errs, (nq ? nq : 1) * sizeof *errs);
        geom__free(m->has_alloc ? &m->alloc : NULL, works, (nq ? nq : 1) * sizeof *works);
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
