/* Error of a mesh against a field: |f - iso| / |grad f| at vertices and at
 * triangle samples (centroid and edge midpoints). */
#include "iso/iso_internal.h"

#include <string.h>
#ifdef GEOM_ISO_OPENMP
#include <omp.h>
#endif

void geom__iso_field_gradient(const geom_iso_field *f, const double p[3], const double h[3],
                        double g[3], size_t *evals)
{
    if (f->gradient) {
        f->gradient(f->user, p, g);
        *evals += 1;
        return;
    }
    for (int a = 0; a < 3; a++) {
        double q[3] = {p[0], p[1], p[2]};
        double step = h[a];
        q[a] = p[a] + step;
        double up = q[a];
        double fp = f->value(f->user, q);
        q[a] = p[a] - step;
        double dn = q[a];
        double fm = f->value(f->user, q);
        double den = up - dn; /* the step actually taken, after rounding */
        g[a] = den != 0 ? (fp - fm) / den : 0.0;
    }
    *evals += 6;
}

int geom__iso_point_error(const geom_iso_field *f, double iso, const double p[3], const double h[3],
                    double *e, size_t *evals)
{
    double v = f->value(f->user, p);
    *evals += 1;
    double g[3];
    geom__iso_field_gradient(f, p, h, g, evals);
    double n = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    double d = fabs(v - iso);
    if (!isfinite(d) || !(n > 0) || !isfinite(n))
        return 0;
    *e = d / n;
    return 1;
}

#define CHUNK 2048
#define SUB 512 /* points per batch of value-and-gradient evaluations */

/* The error measure from a value and a gradient (as geom__iso_point_error). */
static int error_of(double iso, double v, const double g[3], double *e)
{
    double n = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    double d = fabs(v - iso);
    if (!isfinite(d) || !(n > 0) || !isfinite(n))
        return 0;
    *e = d / n;
    return 1;
}

static void acc_vertex(iso_err_acc *a, double e)
{
    if (e > a->vmax)
        a->vmax = e;
    a->vsum += e;
    a->vcount++;
}

static void acc_sample(iso_err_acc *a, double e)
{
    if (e > a->smax)
        a->smax = e;
    a->ssum += e;
    a->scount++;
}

/* Measure over vertices and triangles in fixed chunks (so the sums do not
 * depend on the thread count), in parallel when OpenMP is there. */
geom_status geom__iso_measure(const geom_iso_field *f, double iso, size_t nv, const double *xyz,
                        const uint8_t *vmask, size_t nt, const uint32_t *tris, size_t stride,
                        const double h[3], int threads, const geom_allocator *alloc,
                        iso_err_acc *total)
{
    if (stride == 0)
        stride = 1;
    memset(total, 0, sizeof *total);
    size_t nvc = (nv + CHUNK - 1) / CHUNK, ntc = (nt + CHUNK - 1) / CHUNK;
    size_t nchunks = nvc + ntc;
    if (nchunks == 0)
        return GEOM_OK;
    size_t bytes;
    if (geom__size_mul(nchunks, sizeof(iso_err_acc), &bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    iso_err_acc *acc = geom__alloc(alloc, bytes);
    if (!acc)
        return GEOM_ERR_NOMEM;
    memset(acc, 0, bytes);
    long long nch = (long long)nchunks;
#ifdef GEOM_ISO_OPENMP
    int nth = threads > 0 ? threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(nth)
#else
    (void)threads;
#endif
    for (long long ci = 0; ci < nch; ci++) {
        iso_err_acc *a = &acc[ci];
        double e;
        if (f->gradients && f->gradient) {
            /* batched: the same points in the same order, values and
             * gradients from one call per SUB points */
            double pts[3 * SUB], val[SUB], grd[3 * SUB];
            int kind[SUB]; /* 1 vertex, 0 triangle sample */
            size_t np = 0;
            int is_v = (size_t)ci < nvc;
            size_t b = is_v ? (size_t)ci * CHUNK : ((size_t)ci - nvc) * CHUNK;
            size_t end = is_v ? (b + CHUNK < nv ? b + CHUNK : nv) : (b + CHUNK < nt ? b + CHUNK : nt);
            for (size_t i = b; i <= end; i++) {
                if (i == end || np + 4 > SUB) {
                    f->gradients(f->user, np, pts, val, grd);
                    a->evaluations += 2 * np;
                    for (size_t k = 0; k < np; k++) {
                        if (error_of(iso, val[k], grd + 3 * k, &e)) {
                            if (kind[k])
                                acc_vertex(a, e);
                            else
                                acc_sample(a, e);
                        } else
                            a->unmeasured++;
                    }
                    np = 0;
                    if (i == end)
                        break;
                }
                if (i % stride)
                    continue;
                if (is_v) {
                    if (vmask && !vmask[i])
                        continue;
                    memcpy(pts + 3 * np, xyz + 3 * i, 3 * sizeof(double));
                    kind[np++] = 1;
                    continue;
                }
                const double *p[3] = {xyz + 3 * (size_t)tris[3 * i], xyz + 3 * (size_t)tris[3 * i + 1],
                                      xyz + 3 * (size_t)tris[3 * i + 2]};
                for (int c = 0; c < 3; c++) {
                    pts[3 * np + (size_t)c] = (p[0][c] + p[1][c] + p[2][c]) / 3.0;
                    pts[3 * (np + 1) + (size_t)c] = 0.5 * (p[0][c] + p[1][c]);
                    pts[3 * (np + 2) + (size_t)c] = 0.5 * (p[1][c] + p[2][c]);
                    pts[3 * (np + 3) + (size_t)c] = 0.5 * (p[2][c] + p[0][c]);
                }
                for (int k = 0; k < 4; k++)
                    kind[np++] = 0;
            }
            continue;
        }
        if ((size_t)ci < nvc) {
            size_t b = (size_t)ci * CHUNK, end = b + CHUNK < nv ? b + CHUNK : nv;
            for (size_t v = b; v < end; v++) {
                if ((vmask && !vmask[v]) || v % stride)
                    continue;
                if (geom__iso_point_error(f, iso, xyz + 3 * v, h, &e, &a->evaluations))
                    acc_vertex(a, e);
                else
                    a->unmeasured++;
            }
        } else {
            size_t b = ((size_t)ci - nvc) * CHUNK, end = b + CHUNK < nt ? b + CHUNK : nt;
            for (size_t t = b; t < end; t++) {
                if (t % stride)
                    continue;
                const double *p[3] = {xyz + 3 * (size_t)tris[3 * t], xyz + 3 * (size_t)tris[3 * t + 1],
                                      xyz + 3 * (size_t)tris[3 * t + 2]};
                double s[4][3];
                for (int c = 0; c < 3; c++) {
                    s[0][c] = (p[0][c] + p[1][c] + p[2][c]) / 3.0;
                    s[1][c] = 0.5 * (p[0][c] + p[1][c]);
                    s[2][c] = 0.5 * (p[1][c] + p[2][c]);
                    s[3][c] = 0.5 * (p[2][c] + p[0][c]);
                }
                for (int k = 0; k < 4; k++) {
                    if (geom__iso_point_error(f, iso, s[k], h, &e, &a->evaluations))
                        acc_sample(a, e);
                    else
                        a->unmeasured++;
                }
            }
        }
    }
    for (size_t c = 0; c < nchunks; c++) {
        iso_err_acc *a = &acc[c];
        if (a->vmax > total->vmax)
            total->vmax = a->vmax;
        if (a->smax > total->smax)
            total->smax = a->smax;
        total->vsum += a->vsum;
        total->ssum += a->ssum;
        total->vcount += a->vcount;
        total->scount += a->scount;
        total->unmeasured += a->unmeasured;
        total->evaluations += a->evaluations;
    }
    geom__free(alloc, acc, bytes);
    return GEOM_OK;
}

geom_status geom_iso_measure_error(const geom_iso_field *field, double iso, size_t n_vertices,
                                   const double *xyz, size_t n_triangles, const uint32_t *tris,
                                   geom_error_report *vertex_error,
                                   geom_error_report *sample_error, size_t *unmeasured)
{
    if (vertex_error)
        memset(vertex_error, 0, sizeof *vertex_error);
    if (sample_error)
        memset(sample_error, 0, sizeof *sample_error);
    if (unmeasured)
        *unmeasured = 0;
    if (!field || !field->value || !isfinite(iso) || (n_vertices && !xyz) ||
        (n_triangles && !tris))
        return GEOM_ERR_INVALID_ARG;
    for (size_t i = 0; i < 3 * n_triangles; i++)
        if (tris[i] >= n_vertices)
            return GEOM_ERR_INVALID_ARG;
    /* Central-difference steps: 1e-5 of the mesh's largest extent. */
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (size_t v = 0; v < n_vertices; v++)
        for (int a = 0; a < 3; a++) {
            double c = xyz[3 * v + a];
            if (!isfinite(c))
                return GEOM_ERR_INVALID_ARG;
            lo[a] = fmin(lo[a], c);
            hi[a] = fmax(hi[a], c);
        }
    double ext = 0;
    for (int a = 0; a < 3; a++)
        if (n_vertices)
            ext = fmax(ext, hi[a] - lo[a]);
    double step = ext > 0 ? 1e-5 * ext : 1e-5;
    double h[3] = {step, step, step};
    iso_err_acc acc;
    geom_status st = geom__iso_measure(field, iso, n_vertices, xyz, NULL, n_triangles, tris, 1, h, 1,
                                       NULL, &acc);
    if (st != GEOM_OK)
        return st;
    if (vertex_error) {
        vertex_error->max_error = acc.vmax;
        vertex_error->mean_error = acc.vcount ? acc.vsum / (double)acc.vcount : 0.0;
        vertex_error->method = GEOM_ERROR_SAMPLED;
        vertex_error->evaluations = acc.evaluations;
    }
    if (sample_error) {
        sample_error->max_error = acc.smax;
        sample_error->mean_error = acc.scount ? acc.ssum / (double)acc.scount : 0.0;
        sample_error->method = GEOM_ERROR_SAMPLED;
        sample_error->evaluations = acc.evaluations;
    }
    if (unmeasured)
        *unmeasured = acc.unmeasured;
    return GEOM_OK;
}
