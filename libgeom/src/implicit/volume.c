/*
 * Dense sampled volumes: creation, trilinear evaluation with
 * central-difference gradients, the field adapter, and the deprecated raw
 * and NRRD entry points (thin wrappers of volume_formats.c's reader).
 */
#include "implicit/implicit_internal.h"

#include <string.h>

/* The description (one geom_implicit_grid: dims, type, spacing never 0,
 * origin, data = the owned samples) and the allocation. */
struct geom_implicit_volume {
    geom_implicit_grid g;
    void *data;
    size_t nbytes;
    geom_allocator alloc;
};

static size_t scalar_size(geom_implicit_scalar t)
{
    return t == GEOM_IMPLICIT_SCALAR_F32 ? 4 : t == GEOM_IMPLICIT_SCALAR_F64 ? 8 : 0;
}

/* Check a description; fill the sample count and byte size. */
static geom_status check_desc(const geom_implicit_grid *d, size_t *count, size_t *bytes)
{
    if (!d || scalar_size(d->type) == 0)
        return GEOM_ERR_INVALID_ARG;
    size_t n = 1;
    for (int a = 0; a < 3; a++) {
        if (d->dims[a] == 0)
            return GEOM_ERR_INVALID_ARG;
        if (!isfinite(d->origin[a]) || !isfinite(d->spacing[a]) || d->spacing[a] < 0.0)
            return GEOM_ERR_INVALID_ARG;
        if (geom__size_mul(n, d->dims[a], &n) != GEOM_OK)
            return GEOM_ERR_LIMIT;
    }
    if (geom__size_mul(n, scalar_size(d->type), bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    *count = n;
    return GEOM_OK;
}

geom_status geom_implicit_volume_create(const geom_implicit_grid *desc,
                                        const geom_allocator *alloc,
                                        geom_implicit_volume **out)
{
    if (out)
        *out = NULL;
    if (!out)
        return GEOM_ERR_INVALID_ARG;
    size_t count, bytes;
    geom_status st = check_desc(desc, &count, &bytes);
    if (st != GEOM_OK)
        return st;
    geom_implicit_volume *v = geom__alloc(alloc, sizeof *v);
    if (!v)
        return GEOM_ERR_NOMEM;
    memset(v, 0, sizeof *v);
    if (alloc)
        v->alloc = *alloc;
    v->data = geom__alloc(alloc, bytes);
    if (!v->data) {
        geom__free(alloc, v, sizeof *v);
        return GEOM_ERR_NOMEM;
    }
    memset(v->data, 0, bytes);
    v->nbytes = bytes;
    v->g.type = desc->type;
    v->g.data = v->data;
    for (int a = 0; a < 3; a++) {
        v->g.dims[a] = desc->dims[a];
        v->g.spacing[a] = desc->spacing[a] > 0.0 ? desc->spacing[a] : 1.0;
        v->g.origin[a] = desc->origin[a];
    }
    *out = v;
    return GEOM_OK;
}

void geom_implicit_volume_destroy(geom_implicit_volume *v)
{
    if (!v)
        return;
    geom_allocator a = v->alloc;
    geom__free(&a, v->data, v->nbytes);
    geom__free(&a, v, sizeof *v);
}

void geom_implicit_volume_get_desc(const geom_implicit_volume *v, geom_implicit_grid *out)
{
    if (!v || !out)
        return;
    *out = v->g;
}

void *geom_implicit_volume_data(geom_implicit_volume *v)
{
    return v ? v->data : NULL;
}

const void *geom_implicit_volume_cdata(const geom_implicit_volume *v)
{
    return v ? v->data : NULL;
}

double geom_implicit_volume_at(const geom_implicit_volume *v, size_t i, size_t j, size_t k)
{
    if (!v || i >= v->g.dims[0] || j >= v->g.dims[1] || k >= v->g.dims[2])
        return NAN;
    size_t idx = i + v->g.dims[0] * (j + v->g.dims[1] * k);
    if (v->g.type == GEOM_IMPLICIT_SCALAR_F32)
        return (double)((const float *)v->data)[idx];
    return ((const double *)v->data)[idx];
}

geom_aabb geom_implicit_volume_bounds(const geom_implicit_volume *v)
{
    if (!v)
        return geom_aabb_empty();
    geom_aabb b;
    double lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = v->g.origin[a];
        hi[a] = v->g.origin[a] + (double)(v->g.dims[a] - 1) * v->g.spacing[a];
    }
    b.min = geom_vec3_make(lo[0], lo[1], lo[2]);
    b.max = geom_vec3_make(hi[0], hi[1], hi[2]);
    return b;
}

double geom_implicit_volume_eval(const geom_implicit_volume *v, const double p[3])
{
    if (!v)
        return NAN;
    return geom_implicit_samples_value(&v->g, v->data, p);
}

double geom_implicit_volume_eval_grad(const geom_implicit_volume *v, const double p[3],
                                      double grad[3])
{
    double val = geom_implicit_volume_eval(v, p);
    if (!grad)
        return val;
    if (!v) {
        grad[0] = grad[1] = grad[2] = NAN;
        return val;
    }
    geom_implicit_samples_gradient(&v->g, v->data, p, grad);
    return val;
}

double geom_implicit_volume_value_cb(void *user, const double p[3])
{
    return geom_implicit_volume_eval((const geom_implicit_volume *)user, p);
}

double geom_implicit_volume_grad_cb(void *user, const double p[3], double grad[3])
{
    return geom_implicit_volume_eval_grad((const geom_implicit_volume *)user, p, grad);
}

void geom_implicit_field_from_volume(const geom_implicit_volume *v, geom_implicit_field *out)
{
    if (!out)
        return;
    memset(out, 0, sizeof *out);
    out->value = geom_implicit_volume_value_cb;
    out->gradient = geom_implicit_volume_grad_cb;
    out->user = (void *)(uintptr_t)v;
    out->exact = 0;
}

/* ------------------------------------------- deprecated reader entry points */

geom_status geom_implicit_volume_read_raw(const char *path, const geom_implicit_grid *desc,
                                          const geom_allocator *alloc,
                                          geom_implicit_volume **out, geom_diag *diag)
{
    if (out)
        *out = NULL;
    size_t count, bytes;
    geom_status st = check_desc(desc, &count, &bytes);
    if (path && out && st != GEOM_OK)
        return geom__diag_set(diag, st, path, 0, 0,
                             st == GEOM_ERR_LIMIT ? "volume dimensions too large"
                                                  : "invalid volume description");
    geom_implicit_volume_read_options o;
    memset(&o, 0, sizeof o);
    o.format = GEOM_IMPLICIT_VOLUME_RAW;
    if (desc) {
        for (int a = 0; a < 3; a++) {
            o.dims[a] = desc->dims[a];
            o.spacing[a] = desc->spacing[a];
            o.origin[a] = desc->origin[a];
        }
        o.sample = desc->type == GEOM_IMPLICIT_SCALAR_F32 ? GEOM_IMPLICIT_SAMPLE_F32
                                                          : GEOM_IMPLICIT_SAMPLE_F64;
        o.big_endian = desc->big_endian;
    }
    return geom_implicit_volume_read(path, &o, alloc, out, NULL, diag);
}

geom_status geom_implicit_volume_read_nrrd_memory(const void *data, size_t size,
                                                  const char *source_name,
                                                  const geom_allocator *alloc,
                                                  geom_implicit_volume **out, geom_diag *diag)
{
    geom_implicit_volume_read_options o;
    memset(&o, 0, sizeof o);
    o.format = GEOM_IMPLICIT_VOLUME_NRRD;
    return geom_implicit_volume_read_memory(data, size, source_name, &o, alloc, out, NULL, diag);
}

geom_status geom_implicit_volume_read_nrrd(const char *path, const geom_allocator *alloc,
                                           geom_implicit_volume **out, geom_diag *diag)
{
    geom_implicit_volume_read_options o;
    memset(&o, 0, sizeof o);
    o.format = GEOM_IMPLICIT_VOLUME_NRRD;
    return geom_implicit_volume_read(path, &o, alloc, out, NULL, diag);
}
