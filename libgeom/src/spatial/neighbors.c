/* Variable-length query answers: per-query rows computed in parallel chunks
 * and assembled in query order (so the output does not depend on the thread
 * count), and their sorting. */
#include "spatial/spatial_internal.h"

#include <stdlib.h>
#include <string.h>

#define CHUNK 256

void geom_neighbors_free(geom_neighbors *nb)
{
    if (!nb)
        return;
    const geom_allocator *a = nb->alloc;
    size_t total = nb->offsets ? nb->offsets[nb->query_count] : 0;
    geom__free(a, nb->offsets, (nb->query_count + 1) * sizeof *nb->offsets);
    geom__free(a, nb->index, (nb->capacity ? nb->capacity : total) * sizeof *nb->index);
    geom__free(a, nb->distance, (nb->capacity ? nb->capacity : total) * sizeof *nb->distance);
    memset(nb, 0, sizeof *nb);
}

static int hit_cmp(const void *pa, const void *pb)
{
    const geom__hit *a = pa, *b = pb;
    if (a->d2 < b->d2) return -1;
    if (a->d2 > b->d2) return 1;
    return (a->idx > b->idx) - (a->idx < b->idx);
}

void geom__hits_sort(geom__hits *hs, size_t from)
{
    size_t m = hs->n - from;
    if (m < 2)
        return;
    geom__hit *h = hs->h + from;
    if (m <= 16) {
        for (size_t i = 1; i < m; i++) {
            geom__hit x = h[i];
            size_t j = i;
            while (j > 0 && hit_cmp(&x, &h[j - 1]) < 0) {
                h[j] = h[j - 1];
                j--;
            }
            h[j] = x;
        }
        return;
    }
    qsort(h, m, sizeof *h, hit_cmp);
}

size_t geom__first_nonfinite(const double *p, size_t n, int dim)
{
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < dim; k++)
            if (!isfinite(p[(size_t)dim * i + (size_t)k]))
                return i;
    return n;
}

geom_status geom__radius_query_check(const double *queries, size_t nq, int dim, double r,
                                     geom_diag *diag)
{
    if (!(r >= 0) || !isfinite(r))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "radius query: radius %g (must be finite and >= 0)", r);
    size_t bad = geom__first_nonfinite(queries, nq, dim);
    if (bad < nq)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "radius query: query %zu has a NaN/Inf coordinate", bad);
    return GEOM_OK;
}

typedef struct chunk {
    geom__hits hits;
    size_t counts[CHUNK];
    geom_status st;
} chunk;

geom_status geom__batch_rows(const geom_allocator *a, size_t nq, geom__row_fn fn, const void *ctx,
                             int threads, int with_dist, geom_neighbors *out)
{
    geom_neighbors_free(out);
    out->alloc = a;
    size_t nch = (nq + CHUNK - 1) / CHUNK;
    chunk *ch = geom__alloc(a, (nch ? nch : 1) * sizeof *ch);
    out->offsets = geom__alloc(a, (nq + 1) * sizeof *out->offsets);
    if (!ch || !out->offsets) {
        geom__free(a, ch, (nch ? nch : 1) * sizeof *ch);
        geom__free(a, out->offsets, (nq + 1) * sizeof *out->offsets);
        out->offsets = NULL;
        return GEOM_ERR_NOMEM;
    }
    out->query_count = nq;
    memset(ch, 0, (nch ? nch : 1) * sizeof *ch);
    ptrdiff_t nc = (ptrdiff_t)nch;
    int nth = geom__spatial_threads(threads);
    (void)nth;
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(nth) if (nch > 1)
#endif
    for (ptrdiff_t c = 0; c < nc; c++) {
        chunk *k = &ch[c];
        k->hits.a = a;
        size_t q0 = (size_t)c * CHUNK, q1 = q0 + CHUNK < nq ? q0 + CHUNK : nq;
        for (size_t q = q0; q < q1; q++) {
            size_t before = k->hits.n;
            geom_status st = fn(ctx, q, &k->hits);
            if (st != GEOM_OK) {
                k->st = st;
                break;
            }
            k->counts[q - q0] = k->hits.n - before;
        }
    }
    geom_status st = GEOM_OK;
    size_t total = 0;
    for (size_t c = 0; c < nch; c++) {
        if (ch[c].st != GEOM_OK)
            st = ch[c].st;
        total += ch[c].hits.n;
    }
    if (st == GEOM_OK) {
        out->index = geom__alloc(a, (total ? total : 1) * sizeof *out->index);
        if (with_dist)
            out->distance = geom__alloc(a, (total ? total : 1) * sizeof *out->distance);
        out->capacity = total ? total : 1;
        if (!out->index || (with_dist && !out->distance))
            st = GEOM_ERR_NOMEM;
    }
    if (st == GEOM_OK) {
        size_t pos = 0;
        out->offsets[0] = 0;
        for (size_t c = 0; c < nch; c++) {
            size_t q0 = c * CHUNK, q1 = q0 + CHUNK < nq ? q0 + CHUNK : nq;
            for (size_t q = q0; q < q1; q++)
                out->offsets[q + 1] = out->offsets[q] + ch[c].counts[q - q0];
            for (size_t i = 0; i < ch[c].hits.n; i++) {
                out->index[pos] = ch[c].hits.h[i].idx;
                if (with_dist)
                    out->distance[pos] = with_dist == 2 ? ch[c].hits.h[i].d2 : sqrt(ch[c].hits.h[i].d2);
                pos++;
            }
        }
    }
    for (size_t c = 0; c < nch; c++)
        geom__free(a, ch[c].hits.h, ch[c].hits.cap * sizeof *ch[c].hits.h);
    geom__free(a, ch, (nch ? nch : 1) * sizeof *ch);
    if (st != GEOM_OK) {
        geom__free(a, out->index, out->capacity * sizeof *out->index);
        geom__free(a, out->distance, out->capacity * sizeof *out->distance);
        geom__free(a, out->offsets, (nq + 1) * sizeof *out->offsets);
        memset(out, 0, sizeof *out);
    }
    return st;
}

geom_status geom__knn_batch(const geom_allocator *a, const void *ctx, geom__knn_fn one, int dim,
                            size_t n, const double *queries, size_t nq, size_t k, uint32_t *index,
                            double *distance, int threads, geom_diag *diag)
{
    if (nq && !queries)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "kNN: NULL argument");
    size_t bad = geom__first_nonfinite(queries, nq, dim);
    if (bad < nq)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "kNN: query %zu has a NaN/Inf coordinate", bad);
    if (k == 0 || nq == 0)
        return GEOM_OK;
    size_t kk = k < n ? k : n;
    ptrdiff_t nn = (ptrdiff_t)nq;
    int nth = geom__spatial_threads(threads);
    (void)nth;
    geom_status st = GEOM_OK;
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp parallel num_threads(nth) if (nq > 64)
#endif
    {
        double sd2[64];
        uint32_t sid[64];
        double *d2 = kk <= 64 ? sd2 : geom__alloc(a, kk * sizeof *d2);
        uint32_t *id = kk <= 64 ? sid : geom__alloc(a, kk * sizeof *id);
        if (!d2 || !id) {
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp atomic write
#endif
            st = GEOM_ERR_NOMEM;
        } else {
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp for schedule(dynamic, 256)
#endif
            for (ptrdiff_t qi = 0; qi < nn; qi++) {
                double q[3];
                geom__load_query(queries, (size_t)qi, dim, q);
                geom__kbest b = {d2, id, kk, 0};
                one(ctx, q, &b);
                for (size_t j = 0; j < k; j++) {
                    size_t o = (size_t)qi * k + j;
                    if (index)
                        index[o] = j < b.count ? id[j] : GEOM_INVALID_INDEX;
                    if (distance)
                        distance[o] = j < b.count ? sqrt(d2[j]) : INFINITY;
                }
            }
        }
        if (kk > 64) {
            geom__free(a, d2, kk * sizeof *d2);
            geom__free(a, id, kk * sizeof *id);
        }
    }
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, "", 0, 0, "kNN: out of memory");
    return GEOM_OK;
}
