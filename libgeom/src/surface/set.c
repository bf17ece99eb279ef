/* Owning lists of surfaces (what the file readers return). */
#include "surface/surface_internal.h"

#include <string.h>

#define NAME_MAX_BYTES 64

struct geom_surface_set {
    geom_allocator alloc;
    int has_alloc;
    geom_nurbs_surface *views; /* count entries, borrowing blocks[i] */
    double **blocks;
    size_t *block_sizes; /* bytes */
    char (*names)[NAME_MAX_BYTES];
    size_t count, cap;
};

static const geom_allocator *set_alloc(const geom_surface_set *s)
{
    return s->has_alloc ? &s->alloc : NULL;
}

geom_surface_set *geom_surface_set_create(const geom_allocator *alloc)
{
    geom_surface_set *s = geom__alloc(alloc, sizeof *s);
    if (!s)
        return NULL;
    memset(s, 0, sizeof *s);
    if (alloc) {
        s->alloc = *alloc;
        s->has_alloc = 1;
    }
    return s;
}

void geom_surface_set_destroy(geom_surface_set *set)
{
    if (!set)
        return;
    const geom_allocator *a = set_alloc(set);
    for (size_t i = 0; i < set->count; ++i)
        geom__free(a, set->blocks[i], set->block_sizes[i]);
    geom__free(a, set->views, set->cap * sizeof *set->views);
    geom__free(a, set->blocks, set->cap * sizeof *set->blocks);
    geom__free(a, set->block_sizes, set->cap * sizeof *set->block_sizes);
    geom__free(a, set->names, set->cap * sizeof *set->names);
    geom_allocator copy = set->alloc;
    int has = set->has_alloc;
    geom__free(has ? &copy : NULL, set, sizeof *set);
}

size_t geom_surface_set_count(const geom_surface_set *set)
{
    return set ? set->count : 0;
}

const geom_nurbs_surface *geom_surface_set_data(const geom_surface_set *set)
{
    return set && set->count ? set->views : NULL;
}

const char *geom_surface_set_name(const geom_surface_set *set, size_t i)
{
    if (!set || i >= set->count)
        return NULL;
    return set->names[i];
}

static geom_status grow(geom_surface_set *set)
{
    if (set->count < set->cap)
        return GEOM_OK;
    const geom_allocator *a = set_alloc(set);
    size_t nc = set->cap ? 2 * set->cap : 8;
    if (nc > SIZE_MAX / 256)
        return GEOM_ERR_LIMIT;
    /* all four arrays or none, so the recorded capacity stays right */
    geom_nurbs_surface *v = geom__alloc(a, nc * sizeof *v);
    double **b = geom__alloc(a, nc * sizeof *b);
    size_t *bs = geom__alloc(a, nc * sizeof *bs);
    char(*nm)[NAME_MAX_BYTES] = geom__alloc(a, nc * sizeof *nm);
    if (!v || !b || !bs || !nm) {
        geom__free(a, v, nc * sizeof *v);
        geom__free(a, b, nc * sizeof *b);
        geom__free(a, bs, nc * sizeof *bs);
        geom__free(a, nm, nc * sizeof *nm);
        return GEOM_ERR_NOMEM;
    }
    if (set->count) {
        memcpy(v, set->views, set->count * sizeof *v);
        memcpy(b, set->blocks, set->count * sizeof *b);
        memcpy(bs, set->block_sizes, set->count * sizeof *bs);
        memcpy(nm, set->names, set->count * sizeof *nm);
    }
    geom__free(a, set->views, set->cap * sizeof *set->views);
    geom__free(a, set->blocks, set->cap * sizeof *set->blocks);
    geom__free(a, set->block_sizes, set->cap * sizeof *set->block_sizes);
    geom__free(a, set->names, set->cap * sizeof *set->names);
    set->views = v;
    set->blocks = b;
    set->block_sizes = bs;
    set->names = nm;
    set->cap = nc;
    return GEOM_OK;
}

geom_status geom_surface_set_add(geom_surface_set *set, const geom_nurbs_surface *s,
                                 const char *name)
{
    if (!set || geom__surface_check_cheap(s) != GEOM_OK)
        return GEOM_ERR_INVALID_ARG;
    size_t nku = s->nu + (size_t)s->degree_u + 1, nkv = s->nv + (size_t)s->degree_v + 1;
    size_t npts, total;
    if (geom__size_mul(s->nu, s->nv, &npts) != GEOM_OK || npts > SIZE_MAX / 8)
        return GEOM_ERR_LIMIT;
    total = nku + nkv + 3 * npts + (s->weights ? npts : 0);
    size_t bytes;
    if (geom__size_mul(total, sizeof(double), &bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    geom_status st = grow(set);
    if (st != GEOM_OK)
        return st;
    const geom_allocator *a = set_alloc(set);
    double *blk = geom__alloc(a, bytes);
    if (!blk)
        return GEOM_ERR_NOMEM;
    double *ku = blk, *kv = ku + nku, *pts = kv + nkv, *w = pts + 3 * npts;
    memcpy(ku, s->knots_u, nku * sizeof(double));
    memcpy(kv, s->knots_v, nkv * sizeof(double));
    memcpy(pts, s->points, 3 * npts * sizeof(double));
    if (s->weights)
        memcpy(w, s->weights, npts * sizeof(double));
    geom_nurbs_surface *v = &set->views[set->count];
    *v = *s;
    v->knots_u = ku;
    v->knots_v = kv;
    v->points = pts;
    v->weights = s->weights ? w : NULL;
    set->blocks[set->count] = blk;
    set->block_sizes[set->count] = bytes;
    set->names[set->count][0] = '\0';
    if (name) {
        size_t l = strlen(name);
        if (l >= NAME_MAX_BYTES)
            l = NAME_MAX_BYTES - 1;
        memcpy(set->names[set->count], name, l);
        set->names[set->count][l] = '\0';
    }
    set->count++;
    return GEOM_OK;
}
