/*
 * geom_mesh_build: a polygon soup (vertex positions, faces as index lists)
 * and its attribute streams -> a half-edge mesh. The phases:
 *
 *  1. arguments: NULL arrays, counts, finite coordinates, the streams'
 *     shapes (check_streams);
 *  2. topology, by one of two paths that give the same mesh for the same
 *     input where both apply: build_fast.c, for input that is already an
 *     oriented manifold (tried first, for any input), and build_repair.c,
 *     which validates, orients, cuts non-manifold edges and splits
 *     non-manifold vertices (see there), for the rest;
 *  3. the streams, attached through the origin maps (attach_streams).
 * Debug builds check that a mesh built by the fast path passes
 * geom_mesh_validate.
 */
#include "mesh/build_internal.h"

#include <assert.h>

#define INV GEOM_INVALID_INDEX

void *geom__mesh_bs_alloc(geom__mesh_bscratch *s, size_t n, size_t es)
{
    size_t b;
    if (s->n >= (int)(sizeof s->p / sizeof s->p[0]) || geom__size_mul(n ? n : 1, es, &b) != GEOM_OK)
        return NULL;
    void *p = geom__alloc(s->a, b);
    if (p) {
        s->p[s->n] = p;
        s->sz[s->n] = b;
        s->n++;
    }
    return p;
}

void geom__mesh_bs_free_one(geom__mesh_bscratch *s, void *p)
{
    for (int i = 0; i < s->n; ++i)
        if (s->p[i] == p) {
            geom__free(s->a, p, s->sz[i]);
            s->n--;
            s->p[i] = s->p[s->n];
            s->sz[i] = s->sz[s->n];
            return;
        }
}

void geom__mesh_bs_free_all(geom__mesh_bscratch *s)
{
    while (s->n > 0) {
        s->n--;
        geom__free(s->a, s->p[s->n], s->sz[s->n]);
    }
}

void geom__mesh_report_add(size_t *count, uint32_t *first, uint32_t idx)
{
    if (*count < GEOM_MESH_REPORT_FIRST)
        first[*count] = idx;
    (*count)++;
}

size_t geom__mesh_number_edges(size_t C, const uint32_t *partner, uint32_t *he_of)
{
    size_t E = 0;
    memset(he_of, 0xff, C * sizeof(uint32_t));
    for (size_t c = 0; c < C; ++c) {
        if (he_of[c] != INV)
            continue;
        he_of[c] = (uint32_t)(2 * E);
        if (partner[c] != INV)
            he_of[partner[c]] = (uint32_t)(2 * E + 1);
        E++;
    }
    return 2 * E;
}

/* --------------------------------------------------------- attribute streams */

static geom_status check_streams(const geom_mesh_build_options *opt, size_t nverts, size_t nfaces,
                                 size_t ncorners, geom_diag *diag)
{
    size_t n = opt ? opt->n_channels : 0;
    if (n && !opt->channels)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_mesh_build: NULL channels");
    for (size_t i = 0; i < n; ++i) {
        const geom_mesh_build_channel *c = &opt->channels[i];
        const char *why = NULL;
        size_t nvals = c->domain == GEOM_MESH_DOMAIN_VERTEX ? nverts
                       : c->domain == GEOM_MESH_DOMAIN_FACE ? nfaces
                                                            : c->n_values;
        if (!c->name || !c->name[0] || strlen(c->name) >= GEOM_MESH__NAME_MAX)
            why = "empty or too long name";
        else if (c->domain != GEOM_MESH_DOMAIN_VERTEX && c->domain != GEOM_MESH_DOMAIN_FACE &&
                 c->domain != GEOM_MESH_DOMAIN_CORNER)
            why = "domain must be VERTEX, FACE or CORNER";
        else if (c->ncomp == 0)
            why = "ncomp is 0";
        else if (nvals && !c->values)
            why = "NULL values";
        else if (c->domain == GEOM_MESH_DOMAIN_VERTEX && strcmp(c->name, "position") == 0)
            why = "\"position\" is the positions argument";
        else if (c->domain == GEOM_MESH_DOMAIN_CORNER) {
            if (ncorners && !c->indices)
                why = "NULL corner indices";
            else if (c->n_values >= (size_t)UINT32_MAX)
                why = "pool too large";
            else
                for (size_t k = 0; k < ncorners && !why; ++k)
                    if (c->indices[k] != INV && (size_t)c->indices[k] >= c->n_values)
                        why = "corner index past the pool";
        }
        for (size_t j = 0; j < i && !why; ++j)
            if (opt->channels[j].domain == c->domain &&
                strcmp(opt->channels[j].name, c->name) == 0)
                why = "repeated name";
        if (why)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                 "geom_mesh_build: channel %zu: %s", i, why);
    }
    return GEOM_OK;
}

/* Attach the streams to the built mesh (which has its origin maps).
 * fstart: the input faces' first corners (nfaces + 1 entries). */
static geom_status attach_streams(geom_mesh *m, const geom_mesh_build_options *opt,
                                  const uint32_t *fstart)
{
    size_t n = opt ? opt->n_channels : 0;
    for (size_t i = 0; i < n; ++i) {
        const geom_mesh_build_channel *c = &opt->channels[i];
        const size_t nc = c->ncomp;
        uint32_t id;
        geom_status st = geom_mesh_channel_add(m, c->name, c->domain, nc, &id);
        if (st != GEOM_OK)
            return st;
        if (c->domain == GEOM_MESH_DOMAIN_VERTEX) {
            double *d = m->channels[id].data;
            for (size_t v = 0; v < m->nv; ++v)
                memcpy(d + v * nc, c->values + (size_t)m->vertex_origin[v] * nc,
                       nc * sizeof(double));
        } else if (c->domain == GEOM_MESH_DOMAIN_FACE) {
            double *d = m->channels[id].data;
            for (size_t f = 0; f < m->nf; ++f)
                memcpy(d + f * nc, c->values + (size_t)m->face_origin[f] * nc,
                       nc * sizeof(double));
        } else {
            if ((st = geom_mesh_corner_pool_resize(m, id, c->n_values)) != GEOM_OK)
                return st;
            geom__mesh_channel *ch = &m->channels[id];
            if (c->n_values)
                memcpy(ch->data, c->values, c->n_values * nc * sizeof(double));
            uint32_t *ci = ch->corner;
            for (size_t f = 0; f < m->nf; ++f) {
                /* input corner k: k next-steps from f_he when not flipped,
                 * (n - k) % n (k prev-steps) when flipped */
                const uint32_t *src = c->indices + fstart[m->face_origin[f]];
                uint32_t h0 = m->f_he[f], h = h0;
                size_t k = 0;
                if (!m->face_flipped[f]) {
                    do {
                        ci[h] = src[k++];
                        h = m->he_next[h];
                    } while (h != h0);
                } else {
                    do {
                        ci[h] = src[k++];
                        h = m->he_prev[h];
                    } while (h != h0);
                }
            }
        }
    }
    return GEOM_OK;
}

geom_status geom_mesh_build(geom_mesh *m, size_t nverts, const double *xyz, size_t nfaces,
                            const uint32_t *face_sizes, const uint32_t *indices,
                            const geom_mesh_build_options *opt, geom_mesh_build_report *report,
                            geom_diag *diag)
{
    geom_mesh_build_report rep_local;
    geom_mesh_build_report *rep = report ? report : &rep_local;
    memset(rep, 0, sizeof *rep);
    if (!m || (nverts && !xyz) || (nfaces && !face_sizes))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_mesh_build: NULL argument");
    if (nverts >= (size_t)UINT32_MAX || nfaces >= (size_t)UINT32_MAX)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0,
                             "geom_mesh_build: more than 2^32-2 vertices or faces");
    for (size_t i = 0; i < nverts; ++i)
        if (!geom__isfinite3(xyz + 3 * i))
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                 "geom_mesh_build: vertex %zu has a non-finite coordinate", i);
    size_t nch = opt ? opt->n_channels : 0;
    uint32_t *fstart = NULL;
    size_t ncorners = 0;
    geom_status st;
    if (nch) {
        /* input corner offsets of the faces, for the streams */
        size_t bytes;
        if (geom__size_mul(nfaces + 1, sizeof(uint32_t), &bytes) != GEOM_OK)
            return geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0, "geom_mesh_build: too large for 32-bit indices");
        fstart = geom__alloc(&m->alloc, bytes);
        if (!fstart)
            return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "geom_mesh_build: out of memory");
        for (size_t f = 0; f < nfaces; ++f) {
            fstart[f] = (uint32_t)ncorners;
            ncorners += face_sizes[f];
            if (ncorners > (size_t)INT32_MAX) {
                geom__free(&m->alloc, fstart, bytes);
                return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0,
                                     "geom_mesh_build: more than 2^31 face corners");
            }
        }
        fstart[nfaces] = (uint32_t)ncorners;
        if ((st = check_streams(opt, nverts, nfaces, ncorners, diag)) != GEOM_OK) {
            geom__free(&m->alloc, fstart, bytes);
            return st;
        }
    }
    /* the fast path first, for any input: it declines what needs a repair */
    st = GEOM_OK;
    int repair = geom__mesh_build_fast(m, nverts, xyz, nfaces, face_sizes, indices, rep, &st) ==
                 GEOM_MESH__NEEDS_REPAIR;
    if (repair && st == GEOM_OK) {
        memset(rep, 0, sizeof *rep);
        st = geom__mesh_build_repair(m, nverts, xyz, nfaces, face_sizes, indices,
                                     opt && opt->skip_invalid_faces, opt && opt->keep_orientation,
                                     rep, diag);
    }
    if (st == GEOM_OK && nch) {
        st = attach_streams(m, opt, fstart);
        if (st != GEOM_OK)
            geom__mesh_clear_all(m);
    }
    if (fstart)
        geom__free(&m->alloc, fstart, (nfaces + 1) * sizeof(uint32_t));
#ifndef NDEBUG
    if (st == GEOM_OK && !repair) {
        /* the fast path must give what the repairing one gives: a mesh
         * that passes every check (when the check itself can run: it may
         * run out of memory) */
        size_t nd = 0;
        geom_status vs = geom_mesh_validate(m, NULL, 0, &nd);
        assert(vs != GEOM_OK || nd == 0);
        (void)vs;
        (void)nd;
    }
#endif
    return st;
}
