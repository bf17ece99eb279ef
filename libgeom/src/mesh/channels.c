/* Attribute channels: VERTEX, FACE, EDGE values and CORNER (face-varying)
 * pools with per-halfedge indices. */
#include "mesh/mesh_internal.h"

#define INV GEOM_INVALID_INDEX

static size_t domain_count(const geom_mesh *m, geom_mesh_domain d)
{
    switch (d) {
    case GEOM_MESH_DOMAIN_VERTEX: return m->nv;
    case GEOM_MESH_DOMAIN_FACE: return m->nf;
    case GEOM_MESH_DOMAIN_EDGE: return m->nh / 2;
    case GEOM_MESH_DOMAIN_CORNER: break;
    }
    return 0;
}

static size_t domain_capacity(const geom_mesh *m, geom_mesh_domain d)
{
    switch (d) {
    case GEOM_MESH_DOMAIN_VERTEX: return m->cap_v;
    case GEOM_MESH_DOMAIN_FACE: return m->cap_f;
    case GEOM_MESH_DOMAIN_EDGE: return m->cap_h / 2;
    case GEOM_MESH_DOMAIN_CORNER: break;
    }
    return 0;
}

void geom__mesh_channel_free(geom_mesh *m, geom__mesh_channel *c)
{
    const geom_allocator *a = &m->alloc;
    if (c->domain == GEOM_MESH_DOMAIN_CORNER) {
        geom__free(a, c->data, c->data_cap * c->ncomp * sizeof(double));
        geom__free(a, c->corner, m->cap_h * sizeof(uint32_t));
    } else
        geom__free(a, c->data, domain_capacity(m, c->domain) * c->ncomp * sizeof(double));
    c->data = NULL;
    c->corner = NULL;
    c->data_cap = c->pool = 0;
}

geom_status geom__mesh_pool_reserve(geom_mesh *m, geom__mesh_channel *c, size_t n)
{
    if (n <= c->data_cap)
        return GEOM_OK;
    if (n > (size_t)UINT32_MAX - 1) /* pool values are indexed by uint32 */
        return GEOM_ERR_LIMIT;
    return geom__grow(&m->alloc, (void **)&c->data, &c->data_cap, n, c->ncomp * sizeof(double));
}

size_t geom_mesh_channel_count(const geom_mesh *m) { return m ? m->n_channels : 0; }

geom_status geom_mesh_channel_add(geom_mesh *m, const char *name, geom_mesh_domain domain,
                                  size_t ncomp, uint32_t *id)
{
    if (!m || !name || ncomp < 1 || ncomp > 4096 || (unsigned)domain > GEOM_MESH_DOMAIN_CORNER)
        return GEOM_ERR_INVALID_ARG;
    size_t len = strlen(name);
    if (len == 0 || len >= GEOM_MESH__NAME_MAX)
        return GEOM_ERR_INVALID_ARG;
    if (geom_mesh_channel_find(m, name, domain) != INV)
        return GEOM_ERR_INVALID_ARG;
    if (m->n_channels >= (size_t)UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;
    geom_status s = geom__mesh_reserve_some(m);
    if (s != GEOM_OK)
        return s;
    void *arr = m->channels;
    s = geom__grow(&m->alloc, &arr, &m->cap_channels, m->n_channels + 1,
                        sizeof *m->channels);
    m->channels = arr;
    if (s != GEOM_OK)
        return s;
    geom__mesh_channel c;
    memset(&c, 0, sizeof c);
    memcpy(c.name, name, len + 1);
    c.domain = domain;
    c.ncomp = ncomp;
    if (domain == GEOM_MESH_DOMAIN_CORNER) {
        size_t nb;
        if (geom__size_mul(m->cap_h, sizeof(uint32_t), &nb) != GEOM_OK)
            return GEOM_ERR_LIMIT;
        c.corner = geom__alloc(&m->alloc, nb);
        if (!c.corner)
            return GEOM_ERR_NOMEM;
        for (size_t i = 0; i < m->cap_h; ++i)
            c.corner[i] = INV;
    } else {
        size_t cap = domain_capacity(m, domain), nb;
        if (geom__size_mul(cap, ncomp * sizeof(double), &nb) != GEOM_OK)
            return GEOM_ERR_LIMIT;
        c.data = geom__alloc(&m->alloc, nb);
        if (!c.data)
            return GEOM_ERR_NOMEM;
        memset(c.data, 0, nb);
        c.data_cap = cap;
    }
    m->channels[m->n_channels] = c;
    if (id)
        *id = (uint32_t)m->n_channels;
    m->n_channels++;
    return GEOM_OK;
}

uint32_t geom_mesh_channel_find(const geom_mesh *m, const char *name, geom_mesh_domain domain)
{
    if (!m || !name)
        return INV;
    for (size_t i = 0; i < m->n_channels; ++i)
        if (m->channels[i].domain == domain && strcmp(m->channels[i].name, name) == 0)
            return (uint32_t)i;
    return INV;
}

geom_status geom_mesh_channel_remove(geom_mesh *m, uint32_t id)
{
    if (!m || id == 0 || (size_t)id >= m->n_channels)
        return GEOM_ERR_INVALID_ARG;
    geom__mesh_channel_free(m, &m->channels[id]);
    memmove(&m->channels[id], &m->channels[id + 1],
            (m->n_channels - id - 1) * sizeof *m->channels);
    m->n_channels--;
    return GEOM_OK;
}

#define CHOK(m, id) ((m) && (size_t)(id) < (m)->n_channels)

const char *geom_mesh_channel_name(const geom_mesh *m, uint32_t id)
{
    return CHOK(m, id) ? m->channels[id].name : NULL;
}

geom_mesh_domain geom_mesh_channel_domain(const geom_mesh *m, uint32_t id)
{
    return CHOK(m, id) ? m->channels[id].domain : GEOM_MESH_DOMAIN_VERTEX;
}

size_t geom_mesh_channel_ncomp(const geom_mesh *m, uint32_t id)
{
    return CHOK(m, id) ? m->channels[id].ncomp : 0;
}

size_t geom_mesh_channel_size(const geom_mesh *m, uint32_t id)
{
    if (!CHOK(m, id))
        return 0;
    const geom__mesh_channel *c = &m->channels[id];
    return c->domain == GEOM_MESH_DOMAIN_CORNER ? c->pool : domain_count(m, c->domain);
}

double *geom_mesh_channel_data(geom_mesh *m, uint32_t id)
{
    return CHOK(m, id) ? m->channels[id].data : NULL;
}

const double *geom_mesh_channel_cdata(const geom_mesh *m, uint32_t id)
{
    return CHOK(m, id) ? m->channels[id].data : NULL;
}

geom_status geom_mesh_corner_pool_resize(geom_mesh *m, uint32_t id, size_t n)
{
    if (!CHOK(m, id) || m->channels[id].domain != GEOM_MESH_DOMAIN_CORNER)
        return GEOM_ERR_INVALID_ARG;
    geom__mesh_channel *c = &m->channels[id];
    geom_status s = geom__mesh_pool_reserve(m, c, n);
    if (s != GEOM_OK)
        return s;
    if (n > c->pool)
        memset(c->data + c->pool * c->ncomp, 0, (n - c->pool) * c->ncomp * sizeof(double));
    c->pool = n;
    return GEOM_OK;
}

geom_status geom__mesh_corner_channel_store(geom_mesh *m, const char *name, size_t ncomp,
                                            const double *values, size_t npool,
                                            const uint32_t *indices, uint32_t *id)
{
    geom_status st;
    uint32_t cid = geom_mesh_channel_find(m, name, GEOM_MESH_DOMAIN_CORNER);
    if (cid != GEOM_INVALID_INDEX && geom_mesh_channel_ncomp(m, cid) != ncomp) {
        st = geom_mesh_channel_remove(m, cid);
        if (st != GEOM_OK)
            return st;
        cid = GEOM_INVALID_INDEX;
    }
    if (cid == GEOM_INVALID_INDEX) {
        st = geom_mesh_channel_add(m, name, GEOM_MESH_DOMAIN_CORNER, ncomp, &cid);
        if (st != GEOM_OK)
            return st;
    }
    st = geom_mesh_corner_pool_resize(m, cid, npool);
    if (st != GEOM_OK)
        return st;
    double *data = geom_mesh_channel_data(m, cid);
    uint32_t *ix = geom_mesh_corner_indices(m, cid);
    size_t nh = m->nh;
    if ((npool && !data) || (nh && !ix))
        return GEOM_ERR_INVALID_ARG;
    if (npool)
        memcpy(data, values, npool * ncomp * sizeof(double));
    if (nh)
        memcpy(ix, indices, nh * sizeof(uint32_t));
    if (id)
        *id = cid;
    return GEOM_OK;
}

uint32_t *geom_mesh_corner_indices(geom_mesh *m, uint32_t id)
{
    return CHOK(m, id) ? m->channels[id].corner : NULL;
}

const uint32_t *geom_mesh_corner_cindices(const geom_mesh *m, uint32_t id)
{
    return CHOK(m, id) ? m->channels[id].corner : NULL;
}

double *geom_mesh_positions(geom_mesh *m) { return m ? m->channels[0].data : NULL; }
const double *geom_mesh_cpositions(const geom_mesh *m) { return m ? m->channels[0].data : NULL; }
