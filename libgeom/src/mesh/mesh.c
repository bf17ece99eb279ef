/* Half-edge mesh: lifetime, storage, counts, navigation, low-level editing
 * (add_vertex, add_face after pmp-library's / OpenMesh's add_face), deletion
 * and compaction. */
#include "mesh/mesh_internal.h"

#include <stdlib.h>

#define INV GEOM_INVALID_INDEX

/* ------------------------------------------------------------ helpers */

geom_status geom__mesh_strdup(const geom_allocator *a, const char *s, char **out)
{
    *out = NULL;
    if (!s)
        return GEOM_OK;
    size_t n = strlen(s) + 1;
    char *d = geom__alloc(a, n);
    if (!d)
        return GEOM_ERR_NOMEM;
    memcpy(d, s, n);
    *out = d;
    return GEOM_OK;
}

void geom__mesh_strfree(const geom_allocator *a, char *s)
{
    if (s)
        geom__free(a, s, strlen(s) + 1);
}


static void *alloc_n(const geom_allocator *a, size_t n, size_t es)
{
    size_t b;
    if (geom__size_mul(n, es, &b) != GEOM_OK)
        return NULL;
    return geom__alloc(a, b);
}

/* ------------------------------------------------------ domain storage */

enum { DOM_V = 0, DOM_E = 1, DOM_F = 2 };

/* Visit every array of a domain in a fixed order: with assign == 0 read the
 * pointers into vals and their per-element byte sizes into es; with
 * assign != 0 store vals back. Returns the number of arrays. The edge domain
 * counts in edges (halfedge arrays have 2 entries per edge). */
#define SLOT(field, esz)                                                                     \
    do {                                                                                     \
        if (assign)                                                                          \
            (field) = vals[k];                                                               \
        else {                                                                               \
            vals[k] = (field);                                                               \
            es[k] = (esz);                                                                   \
        }                                                                                    \
        ++k;                                                                                 \
    } while (0)

static size_t domain_arrays(geom_mesh *m, int dom, void **vals, size_t *es, int assign)
{
    size_t k = 0;
    if (dom == DOM_V) {
        SLOT(m->v_he, sizeof(uint32_t));
        SLOT(m->v_del, 1);
        if (m->vertex_origin)
            SLOT(m->vertex_origin, sizeof(uint32_t));
    } else if (dom == DOM_E) {
        SLOT(m->he_next, 2 * sizeof(uint32_t));
        SLOT(m->he_prev, 2 * sizeof(uint32_t));
        SLOT(m->he_vertex, 2 * sizeof(uint32_t));
        SLOT(m->he_face, 2 * sizeof(uint32_t));
        SLOT(m->e_del, 1);
    } else {
        SLOT(m->f_he, sizeof(uint32_t));
        SLOT(m->f_del, 1);
        if (m->face_origin)
            SLOT(m->face_origin, sizeof(uint32_t));
        if (m->face_flipped)
            SLOT(m->face_flipped, 1);
        if (m->face_group)
            SLOT(m->face_group, sizeof(uint32_t));
    }
    geom_mesh_domain cd = dom == DOM_V   ? GEOM_MESH_DOMAIN_VERTEX
                          : dom == DOM_E ? GEOM_MESH_DOMAIN_EDGE
                                         : GEOM_MESH_DOMAIN_FACE;
    for (size_t i = 0; i < m->n_channels; ++i) {
        geom__mesh_channel *c = &m->channels[i];
        if (c->domain == cd)
            SLOT(c->data, c->ncomp * sizeof(double));
        else if (dom == DOM_E && c->domain == GEOM_MESH_DOMAIN_CORNER)
            SLOT(c->corner, 2 * sizeof(uint32_t));
    }
    return k;
}
#undef SLOT

static size_t domain_cap(const geom_mesh *m, int dom)
{
    return dom == DOM_V ? m->cap_v : dom == DOM_E ? m->cap_h / 2 : m->cap_f;
}

static void set_domain_cap(geom_mesh *m, int dom, size_t c)
{
    if (dom == DOM_V)
        m->cap_v = c;
    else if (dom == DOM_E)
        m->cap_h = 2 * c;
    else
        m->cap_f = c;
    geom_mesh_domain cd = dom == DOM_V   ? GEOM_MESH_DOMAIN_VERTEX
                          : dom == DOM_E ? GEOM_MESH_DOMAIN_EDGE
                                         : GEOM_MESH_DOMAIN_FACE;
    for (size_t i = 0; i < m->n_channels; ++i)
        if (m->channels[i].domain == cd)
            m->channels[i].data_cap = c;
}

/* Grow every array of a domain to hold `need` elements: all new blocks are
 * allocated first, so a failure changes nothing. */
static geom_status grow_domain_to(geom_mesh *m, int dom, size_t need, int exact)
{
    size_t oc = domain_cap(m, dom);
    if (need <= oc)
        return GEOM_OK;
    size_t limit = dom == DOM_E ? (size_t)UINT32_MAX / 2 : (size_t)UINT32_MAX;
    if (need > limit)
        return GEOM_ERR_LIMIT;
    size_t nc = oc < 16 ? 16 : oc;
    while (nc < need)
        nc = nc > limit / 2 ? limit : nc * 2;
    if (exact)
        nc = need;
    const geom_allocator *a = &m->alloc;
    size_t na = 8 + m->n_channels;
    void **vals = alloc_n(a, 2 * na, sizeof(void *));
    size_t *es = alloc_n(a, na, sizeof(size_t));
    if (!vals || !es) {
        geom__free(a, vals, 2 * na * sizeof(void *));
        geom__free(a, es, na * sizeof(size_t));
        return GEOM_ERR_NOMEM;
    }
    void **nvals = vals + na;
    size_t k = domain_arrays(m, dom, vals, es, 0), i;
    geom_status st = GEOM_OK;
    for (i = 0; i < k; ++i) {
        nvals[i] = alloc_n(a, nc, es[i]);
        if (!nvals[i]) {
            st = GEOM_ERR_NOMEM;
            break;
        }
    }
    if (st != GEOM_OK) {
        while (i-- > 0)
            geom__free(a, nvals[i], nc * es[i]);
    } else {
        for (i = 0; i < k; ++i) {
            if (vals[i] && oc)
                memcpy(nvals[i], vals[i], oc * es[i]);
            geom__free(a, vals[i], oc * es[i]);
        }
        domain_arrays(m, dom, nvals, es, 1);
        set_domain_cap(m, dom, nc);
    }
    geom__free(a, vals, 2 * na * sizeof(void *));
    geom__free(a, es, na * sizeof(size_t));
    return st;
}

static geom_status grow_domain(geom_mesh *m, int dom, size_t need)
{
    return grow_domain_to(m, dom, need, 0);
}

static void free_domain(geom_mesh *m, int dom)
{
    size_t c = domain_cap(m, dom);
    const geom_allocator *a = &m->alloc;
    if (dom == DOM_V) {
        geom__free(a, m->v_he, c * 4);
        geom__free(a, m->v_del, c);
        geom__free(a, m->vertex_origin, c * 4);
        m->v_he = m->vertex_origin = NULL;
        m->v_del = NULL;
    } else if (dom == DOM_E) {
        geom__free(a, m->he_next, c * 8);
        geom__free(a, m->he_prev, c * 8);
        geom__free(a, m->he_vertex, c * 8);
        geom__free(a, m->he_face, c * 8);
        geom__free(a, m->e_del, c);
        m->he_next = m->he_prev = m->he_vertex = m->he_face = NULL;
        m->e_del = NULL;
    } else {
        geom__free(a, m->f_he, c * 4);
        geom__free(a, m->f_del, c);
        geom__free(a, m->face_origin, c * 4);
        geom__free(a, m->face_flipped, c);
        geom__free(a, m->face_group, c * 4);
        m->f_he = m->face_origin = m->face_group = NULL;
        m->f_del = m->face_flipped = NULL;
    }
    geom_mesh_domain cd = dom == DOM_V   ? GEOM_MESH_DOMAIN_VERTEX
                          : dom == DOM_E ? GEOM_MESH_DOMAIN_EDGE
                                         : GEOM_MESH_DOMAIN_FACE;
    for (size_t i = 0; i < m->n_channels; ++i) {
        geom__mesh_channel *ch = &m->channels[i];
        if (ch->domain == cd) {
            geom__free(a, ch->data, c * ch->ncomp * sizeof(double));
            ch->data = NULL;
        } else if (dom == DOM_E && ch->domain == GEOM_MESH_DOMAIN_CORNER) {
            geom__free(a, ch->corner, c * 8);
            ch->corner = NULL;
        }
    }
    set_domain_cap(m, dom, 0);
}

geom_status geom__mesh_reserve(geom_mesh *m, size_t nv, size_t nh, size_t nf)
{
    geom_status s;
    if (nh > (size_t)UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;
    if ((s = grow_domain(m, DOM_V, nv)) != GEOM_OK)
        return s;
    if ((s = grow_domain(m, DOM_E, (nh + 1) / 2)) != GEOM_OK)
        return s;
    return grow_domain(m, DOM_F, nf);
}

static void fill_u32(uint32_t *p, size_t n, uint32_t v)
{
    for (size_t i = 0; i < n; ++i)
        p[i] = v;
}

static size_t count_flags(const uint8_t *f, size_t a, size_t b)
{
    size_t n = 0;
    for (size_t i = a; i < b; ++i)
        n += f[i] != 0;
    return n;
}

geom_status geom__mesh_resize(geom_mesh *m, size_t nv, size_t nh, size_t nf)
{
    geom_status s = geom__mesh_reserve(m, nv, nh, nf);
    if (s != GEOM_OK)
        return s;
    size_t ov = m->nv, oh = m->nh, of = m->nf;
    size_t oe = oh / 2, ne = nh / 2;
    if (nv > ov) {
        fill_u32(m->v_he + ov, nv - ov, INV);
        memset(m->v_del + ov, 0, nv - ov);
        if (m->vertex_origin)
            fill_u32(m->vertex_origin + ov, nv - ov, INV);
    } else
        m->n_del_v -= count_flags(m->v_del, nv, ov);
    if (nh > oh) {
        fill_u32(m->he_next + oh, nh - oh, INV);
        fill_u32(m->he_prev + oh, nh - oh, INV);
        fill_u32(m->he_vertex + oh, nh - oh, INV);
        fill_u32(m->he_face + oh, nh - oh, INV);
        memset(m->e_del + oe, 0, ne - oe);
    } else
        m->n_del_e -= count_flags(m->e_del, ne, oe);
    if (nf > of) {
        fill_u32(m->f_he + of, nf - of, INV);
        memset(m->f_del + of, 0, nf - of);
        if (m->face_origin)
            fill_u32(m->face_origin + of, nf - of, INV);
        if (m->face_flipped)
            memset(m->face_flipped + of, 0, nf - of);
        if (m->face_group)
            fill_u32(m->face_group + of, nf - of, INV);
    } else
        m->n_del_f -= count_flags(m->f_del, nf, of);
    for (size_t i = 0; i < m->n_channels; ++i) {
        geom__mesh_channel *c = &m->channels[i];
        size_t o = 0, n = 0;
        switch (c->domain) {
        case GEOM_MESH_DOMAIN_VERTEX: o = ov, n = nv; break;
        case GEOM_MESH_DOMAIN_EDGE: o = oe, n = ne; break;
        case GEOM_MESH_DOMAIN_FACE: o = of, n = nf; break;
        case GEOM_MESH_DOMAIN_CORNER:
            if (nh > oh)
                fill_u32(c->corner + oh, nh - oh, INV);
            continue;
        }
        if (n > o)
            memset(c->data + o * c->ncomp, 0, (n - o) * c->ncomp * sizeof(double));
    }
    m->nv = nv;
    m->nh = nh;
    m->nf = nf;
    return GEOM_OK;
}

geom_status geom__mesh_reserve_some(geom_mesh *m)
{
    return geom__mesh_reserve(m, m->nv ? m->nv : 1, m->nh ? m->nh : 2, m->nf ? m->nf : 1);
}

/* The origin maps at m's capacities; fill: initialise new ones (INV, 0). */
static geom_status alloc_origins(geom_mesh *m, int fill)
{
    const geom_allocator *a = &m->alloc;
    uint32_t *vo = m->vertex_origin, *fo = m->face_origin;
    uint8_t *ff = m->face_flipped;
    if (!vo)
        vo = alloc_n(a, m->cap_v, sizeof(uint32_t));
    if (!fo)
        fo = alloc_n(a, m->cap_f, sizeof(uint32_t));
    if (!ff)
        ff = alloc_n(a, m->cap_f, 1);
    if (!vo || !fo || !ff) {
        if (vo != m->vertex_origin)
            geom__free(a, vo, m->cap_v * sizeof(uint32_t));
        if (fo != m->face_origin)
            geom__free(a, fo, m->cap_f * sizeof(uint32_t));
        if (ff != m->face_flipped)
            geom__free(a, ff, m->cap_f);
        return GEOM_ERR_NOMEM;
    }
    if (fill && vo != m->vertex_origin)
        fill_u32(vo, m->cap_v, INV);
    if (fill && fo != m->face_origin)
        fill_u32(fo, m->cap_f, INV);
    if (fill && ff != m->face_flipped)
        memset(ff, 0, m->cap_f ? m->cap_f : 1);
    m->vertex_origin = vo;
    m->face_origin = fo;
    m->face_flipped = ff;
    return GEOM_OK;
}

geom_status geom__mesh_ensure_origins(geom_mesh *m)
{
    geom_status s = geom__mesh_reserve_some(m);
    if (s != GEOM_OK)
        return s;
    return alloc_origins(m, 1);
}

geom_status geom__mesh_adopt_positions(geom_mesh *m, double *xyz, size_t nv)
{
    if (m->cap_v != 0 || m->nv != 0 || m->n_channels != 1 || nv == 0 || !xyz)
        return GEOM_ERR_INVALID_ARG;
    const geom_allocator *a = &m->alloc;
    uint32_t *vhe = alloc_n(a, nv, sizeof(uint32_t));
    uint8_t *vdel = alloc_n(a, nv, 1);
    if (!vhe || !vdel) {
        geom__free(a, vhe, nv * sizeof(uint32_t));
        geom__free(a, vdel, nv);
        return GEOM_ERR_NOMEM;
    }
    m->v_he = vhe;
    m->v_del = vdel;
    m->channels[0].data = xyz;
    set_domain_cap(m, DOM_V, nv);
    return GEOM_OK;
}

geom_status geom__mesh_build_storage(geom_mesh *m, size_t nv, size_t nh, size_t nf)
{
    geom__mesh_clear_all(m);
    if (nh > (size_t)UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;
    geom_status s;
    if ((s = grow_domain_to(m, DOM_V, nv ? nv : 1, 1)) != GEOM_OK ||
        (s = grow_domain_to(m, DOM_E, nh ? (nh + 1) / 2 : 1, 1)) != GEOM_OK ||
        (s = grow_domain_to(m, DOM_F, nf ? nf : 1, 1)) != GEOM_OK ||
        (s = alloc_origins(m, 0)) != GEOM_OK)
        return s;
    memset(m->v_del, 0, nv);
    memset(m->e_del, 0, nh / 2);
    memset(m->f_del, 0, nf);
    memset(m->face_flipped, 0, nf);
    m->nv = nv;
    m->nh = nh;
    m->nf = nf;
    return GEOM_OK;
}

void geom__mesh_clear_all(geom_mesh *m)
{
    const geom_allocator *a = &m->alloc;
    for (size_t i = m->n_channels; i-- > 1;)
        geom__mesh_channel_free(m, &m->channels[i]);
    m->n_channels = m->n_channels ? 1 : 0;
    geom__free(a, m->vertex_origin, m->cap_v * sizeof(uint32_t));
    geom__free(a, m->face_origin, m->cap_f * sizeof(uint32_t));
    geom__free(a, m->face_flipped, m->cap_f);
    geom__free(a, m->face_group, m->cap_f * sizeof(uint32_t));
    m->vertex_origin = m->face_origin = m->face_group = NULL;
    m->face_flipped = NULL;
    geom__mesh_meta_free(m);
    m->nv = m->nh = m->nf = 0;
    m->n_del_v = m->n_del_e = m->n_del_f = 0;
}

/* ------------------------------------------------------------ lifetime */

geom_mesh *geom_mesh_create(const geom_allocator *alloc)
{
    geom_mesh *m = geom__alloc(alloc, sizeof *m);
    if (!m)
        return NULL;
    memset(m, 0, sizeof *m);
    if (alloc)
        m->alloc = *alloc;
    m->channels = alloc_n(&m->alloc, 4, sizeof *m->channels);
    if (!m->channels) {
        geom__free(alloc, m, sizeof *m);
        return NULL;
    }
    m->cap_channels = 4;
    memset(m->channels, 0, 4 * sizeof *m->channels);
    geom__mesh_channel *c = &m->channels[0];
    memcpy(c->name, "position", 9);
    c->domain = GEOM_MESH_DOMAIN_VERTEX;
    c->ncomp = 3;
    m->n_channels = 1;
    return m;
}

void geom_mesh_destroy(geom_mesh *m)
{
    if (!m)
        return;
    geom__mesh_clear_all(m);
    free_domain(m, DOM_V);
    free_domain(m, DOM_E);
    free_domain(m, DOM_F);
    geom__free(&m->alloc, m->channels, m->cap_channels * sizeof *m->channels);
    geom_allocator a = m->alloc;
    geom__free(&a, m, sizeof *m);
}

void geom_mesh_clear(geom_mesh *m)
{
    if (m)
        geom__mesh_clear_all(m);
}

geom_status geom__mesh_copy(geom_mesh *c, const geom_mesh *m)
{
    geom__mesh_clear_all(c);
    geom_status s = GEOM_OK;
    for (size_t i = 1; i < m->n_channels && s == GEOM_OK; ++i)
        s = geom_mesh_channel_add(c, m->channels[i].name, m->channels[i].domain,
                                  m->channels[i].ncomp, NULL);
    if (s == GEOM_OK && m->vertex_origin)
        s = geom__mesh_ensure_origins(c);
    if (s == GEOM_OK && m->face_group && !geom_mesh_face_groups(c))
        s = GEOM_ERR_NOMEM;
    if (s == GEOM_OK)
        s = geom__mesh_resize(c, m->nv, m->nh, m->nf);
    if (s == GEOM_OK)
        s = geom__mesh_meta_copy(c, m);
    if (s != GEOM_OK) {
        geom__mesh_clear_all(c);
        return s;
    }
    size_t nv = m->nv, nh = m->nh, nf = m->nf;
    memcpy(c->he_next, m->he_next, nh * 4);
    memcpy(c->he_prev, m->he_prev, nh * 4);
    memcpy(c->he_vertex, m->he_vertex, nh * 4);
    memcpy(c->he_face, m->he_face, nh * 4);
    memcpy(c->v_he, m->v_he, nv * 4);
    memcpy(c->f_he, m->f_he, nf * 4);
    memcpy(c->v_del, m->v_del, nv);
    memcpy(c->e_del, m->e_del, nh / 2);
    memcpy(c->f_del, m->f_del, nf);
    c->n_del_v = m->n_del_v;
    c->n_del_e = m->n_del_e;
    c->n_del_f = m->n_del_f;
    if (m->vertex_origin)
        memcpy(c->vertex_origin, m->vertex_origin, nv * 4);
    if (m->face_origin)
        memcpy(c->face_origin, m->face_origin, nf * 4);
    if (m->face_flipped)
        memcpy(c->face_flipped, m->face_flipped, nf);
    if (m->face_group)
        memcpy(c->face_group, m->face_group, nf * 4);
    for (size_t i = 0; i < m->n_channels; ++i) {
        const geom__mesh_channel *src = &m->channels[i];
        geom__mesh_channel *dst = &c->channels[i];
        size_t n = 0;
        switch (src->domain) {
        case GEOM_MESH_DOMAIN_VERTEX: n = nv; break;
        case GEOM_MESH_DOMAIN_EDGE: n = nh / 2; break;
        case GEOM_MESH_DOMAIN_FACE: n = nf; break;
        case GEOM_MESH_DOMAIN_CORNER:
            n = src->pool;
            if (geom_mesh_corner_pool_resize(c, (uint32_t)i, n) != GEOM_OK) {
                geom__mesh_clear_all(c);
                return GEOM_ERR_NOMEM;
            }
            memcpy(dst->corner, src->corner, nh * 4);
            break;
        }
        if (n)
            memcpy(dst->data, src->data, n * src->ncomp * sizeof(double));
    }
    return GEOM_OK;
}

geom_status geom_mesh_clone(const geom_mesh *m, geom_mesh **out)
{
    if (!m || !out)
        return GEOM_ERR_INVALID_ARG;
    *out = NULL;
    geom_mesh *c = geom_mesh_create(&m->alloc);
    if (!c)
        return GEOM_ERR_NOMEM;
    geom_status s = geom__mesh_copy(c, m);
    if (s != GEOM_OK) {
        geom_mesh_destroy(c);
        return s;
    }
    *out = c;
    return GEOM_OK;
}

geom_status geom__mesh_take(geom_mesh *dst, geom_mesh *src)
{
    const geom_allocator *a = &dst->alloc, *b = &src->alloc;
    geom_status s = GEOM_OK;
    if (a->alloc_fn == b->alloc_fn && a->realloc_fn == b->realloc_fn && a->free_fn == b->free_fn &&
        a->user == b->user) {
        geom_mesh t = *dst; /* the same allocator: swap the contents */
        *dst = *src;
        *src = t;
    } else {
        s = geom__mesh_copy(dst, src);
    }
    geom_mesh_destroy(src);
    return s;
}

void geom__mesh_drop_meta(geom_mesh *m)
{
    geom__free(&m->alloc, m->face_group, m->cap_f * sizeof(uint32_t));
    m->face_group = NULL;
    geom__mesh_meta_free(m);
}

/* -------------------------------------------------------------- counts */

size_t geom_mesh_n_vertices(const geom_mesh *m) { return m ? m->nv : 0; }
size_t geom_mesh_n_halfedges(const geom_mesh *m) { return m ? m->nh : 0; }
size_t geom_mesh_n_edges(const geom_mesh *m) { return m ? m->nh / 2 : 0; }
size_t geom_mesh_n_faces(const geom_mesh *m) { return m ? m->nf : 0; }
size_t geom_mesh_n_live_vertices(const geom_mesh *m) { return m ? m->nv - m->n_del_v : 0; }
size_t geom_mesh_n_live_edges(const geom_mesh *m) { return m ? m->nh / 2 - m->n_del_e : 0; }
size_t geom_mesh_n_live_faces(const geom_mesh *m) { return m ? m->nf - m->n_del_f : 0; }

/* ---------------------------------------------------------- navigation */

#define HOK(m, h) ((m) && (size_t)(h) < (m)->nh)
#define VOK(m, v) ((m) && (size_t)(v) < (m)->nv)
#define FOK(m, f) ((m) && (size_t)(f) < (m)->nf)

uint32_t geom_mesh_he_next(const geom_mesh *m, uint32_t h) { return HOK(m, h) ? m->he_next[h] : INV; }
uint32_t geom_mesh_he_prev(const geom_mesh *m, uint32_t h) { return HOK(m, h) ? m->he_prev[h] : INV; }
uint32_t geom_mesh_he_opposite(const geom_mesh *m, uint32_t h) { return HOK(m, h) ? h ^ 1u : INV; }
uint32_t geom_mesh_he_vertex(const geom_mesh *m, uint32_t h)
{
    return HOK(m, h) ? m->he_vertex[h] : INV;
}
uint32_t geom_mesh_he_from(const geom_mesh *m, uint32_t h)
{
    return HOK(m, h) ? m->he_vertex[h ^ 1u] : INV;
}
uint32_t geom_mesh_he_face(const geom_mesh *m, uint32_t h) { return HOK(m, h) ? m->he_face[h] : INV; }
uint32_t geom_mesh_he_edge(const geom_mesh *m, uint32_t h) { return HOK(m, h) ? h >> 1 : INV; }
uint32_t geom_mesh_edge_he(const geom_mesh *m, uint32_t e, int i)
{
    if (!m || (size_t)e >= m->nh / 2 || (i != 0 && i != 1))
        return INV;
    return 2 * e + (uint32_t)i;
}
uint32_t geom_mesh_vertex_he(const geom_mesh *m, uint32_t v) { return VOK(m, v) ? m->v_he[v] : INV; }
uint32_t geom_mesh_face_he(const geom_mesh *m, uint32_t f) { return FOK(m, f) ? m->f_he[f] : INV; }

bool geom_mesh_he_is_boundary(const geom_mesh *m, uint32_t h)
{
    return HOK(m, h) && m->he_face[h] == INV;
}
bool geom_mesh_edge_is_boundary(const geom_mesh *m, uint32_t e)
{
    if (!m || (size_t)e >= m->nh / 2)
        return false;
    return m->he_face[2 * e] == INV || m->he_face[2 * e + 1] == INV;
}
bool geom_mesh_vertex_is_boundary(const geom_mesh *m, uint32_t v)
{
    if (!VOK(m, v))
        return false;
    uint32_t h = m->v_he[v];
    return h == INV || m->he_face[h] == INV;
}
bool geom_mesh_vertex_is_isolated(const geom_mesh *m, uint32_t v)
{
    return VOK(m, v) && m->v_he[v] == INV;
}

size_t geom_mesh_vertex_valence(const geom_mesh *m, uint32_t v)
{
    if (!VOK(m, v) || m->v_he[v] == INV)
        return 0;
    size_t n = 0;
    uint32_t h0 = m->v_he[v], h = h0;
    do {
        ++n;
        h = geom__mesh_ccw(m, h);
    } while (h != h0 && n <= m->nh);
    return n;
}

size_t geom_mesh_face_valence(const geom_mesh *m, uint32_t f)
{
    if (!FOK(m, f) || m->f_he[f] == INV)
        return 0;
    size_t n = 0;
    uint32_t h0 = m->f_he[f], h = h0;
    do {
        ++n;
        h = m->he_next[h];
    } while (h != h0 && n <= m->nh);
    return n;
}

uint32_t geom_mesh_find_halfedge(const geom_mesh *m, uint32_t a, uint32_t b)
{
    if (!VOK(m, a) || !VOK(m, b) || m->v_he[a] == INV)
        return INV;
    uint32_t h0 = m->v_he[a], h = h0;
    size_t guard = 0;
    do {
        if (m->he_vertex[h] == b)
            return h;
        h = geom__mesh_ccw(m, h);
    } while (h != h0 && ++guard <= m->nh);
    return INV;
}

uint32_t geom_mesh_find_edge(const geom_mesh *m, uint32_t a, uint32_t b)
{
    uint32_t h = geom_mesh_find_halfedge(m, a, b);
    return h == INV ? INV : h >> 1;
}

bool geom_mesh_vertex_is_deleted(const geom_mesh *m, uint32_t v) { return VOK(m, v) && m->v_del[v]; }
bool geom_mesh_edge_is_deleted(const geom_mesh *m, uint32_t e)
{
    return m && (size_t)e < m->nh / 2 && m->e_del[e];
}
bool geom_mesh_face_is_deleted(const geom_mesh *m, uint32_t f) { return FOK(m, f) && m->f_del[f]; }

void geom__mesh_adjust_outgoing(geom_mesh *m, uint32_t v)
{
    uint32_t h0 = m->v_he[v], h = h0;
    if (h == INV)
        return;
    size_t guard = 0;
    do {
        if (m->he_face[h] == INV) {
            m->v_he[v] = h;
            return;
        }
        h = geom__mesh_ccw(m, h);
    } while (h != h0 && ++guard <= m->nh);
}

/* -------------------------------------------------------------- editing */

geom_status geom_mesh_add_vertex(geom_mesh *m, const double p[3], uint32_t *out)
{
    if (!m || !p)
        return GEOM_ERR_INVALID_ARG;
    if (m->nv >= (size_t)UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;
    geom_status s = geom__mesh_resize(m, m->nv + 1, m->nh, m->nf);
    if (s != GEOM_OK)
        return s;
    double *x = geom__mesh_pos(m) + 3 * (m->nv - 1);
    x[0] = p[0];
    x[1] = p[1];
    x[2] = p[2];
    if (out)
        *out = (uint32_t)(m->nv - 1);
    return GEOM_OK;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Undo log for next/prev changes made while re-linking patches: entry i
 * restores he_next (kind 0) or he_prev (kind 1) of h[i] to val[i]. */
typedef struct relink_log {
    uint32_t *h, *val, *kind;
    size_t n;
} relink_log;

static void log_set_next(geom_mesh *m, relink_log *lg, uint32_t a, uint32_t b)
{
    lg->h[lg->n] = a;
    lg->val[lg->n] = m->he_next[a];
    lg->kind[lg->n++] = 0;
    lg->h[lg->n] = b;
    lg->val[lg->n] = m->he_prev[b];
    lg->kind[lg->n++] = 1;
    geom__mesh_link(m, a, b);
}

static void log_undo(geom_mesh *m, relink_log *lg)
{
    while (lg->n > 0) {
        lg->n--;
        if (lg->kind[lg->n])
            m->he_prev[lg->h[lg->n]] = lg->val[lg->n];
        else
            m->he_next[lg->h[lg->n]] = lg->val[lg->n];
    }
}

geom_status geom_mesh_add_face(geom_mesh *m, size_t n, const uint32_t *verts, uint32_t *out)
{
    if (!m || !verts || n < 3)
        return GEOM_ERR_INVALID_ARG;
    for (size_t i = 0; i < n; ++i)
        if ((size_t)verts[i] >= m->nv || m->v_del[verts[i]])
            return GEOM_ERR_INVALID_ARG;
    if (n > (size_t)UINT32_MAX / 4 || m->nf >= (size_t)UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;

    /* Scratch: h, is_new, needs_adjust (n each), cache pairs (<= 3n pairs),
     * relink log (<= 6n entries of 3 words). */
    uint32_t sbuf[16 * 27];
    size_t words = (size_t)n * 27;
    uint32_t *buf = sbuf;
    if (words > sizeof sbuf / sizeof sbuf[0]) {
        buf = alloc_n(&m->alloc, words, sizeof(uint32_t));
        if (!buf)
            return GEOM_ERR_NOMEM;
    }
    uint32_t *h = buf, *is_new = buf + n, *adj = buf + 2 * n, *cache = buf + 3 * n;
    relink_log lg = {buf + 9 * n, buf + 15 * n, buf + 21 * n, 0};
    geom_status st = GEOM_OK;

    /* repeated vertices */
    if (n <= 32) {
        for (size_t i = 0; i < n && st == GEOM_OK; ++i)
            for (size_t j = i + 1; j < n; ++j)
                if (verts[i] == verts[j]) {
                    st = GEOM_ERR_INVALID_ARG;
                    break;
                }
    } else {
        memcpy(h, verts, n * sizeof(uint32_t));
        qsort(h, n, sizeof(uint32_t), cmp_u32);
        for (size_t i = 1; i < n; ++i)
            if (h[i] == h[i - 1])
                st = GEOM_ERR_INVALID_ARG;
    }
    if (st != GEOM_OK)
        goto done;
    /* Room for everything first, so nothing can fail after the first change. */
    if ((st = geom__mesh_reserve(m, m->nv, m->nh + 2 * n, m->nf + 1)) != GEOM_OK)
        goto done;

    for (size_t i = 0; i < n; ++i) {
        if (!geom_mesh_vertex_is_boundary(m, verts[i])) {
            st = GEOM_ERR_NONMANIFOLD; /* interior vertex: no gap for a new face */
            goto done;
        }
        h[i] = geom_mesh_find_halfedge(m, verts[i], verts[(i + 1) % n]);
        is_new[i] = h[i] == INV;
        if (!is_new[i] && m->he_face[h[i]] != INV) {
            st = GEOM_ERR_NONMANIFOLD; /* edge already has a face on this side */
            goto done;
        }
    }

    /* A corner whose two edges are both new at a vertex that already has
     * faces would start a second fan there: a non-manifold vertex. */
    for (size_t i = 0; i < n; ++i) {
        size_t ii = (i + 1) % n;
        if (is_new[i] && is_new[ii] && m->v_he[verts[ii]] != INV) {
            st = GEOM_ERR_NONMANIFOLD;
            goto done;
        }
    }

    /* Re-link patches so consecutive existing halfedges follow each other,
     * moving the patch between them into another free gap at the vertex
     * (applied immediately, undone on failure). */
    for (size_t i = 0; i < n; ++i) {
        size_t ii = (i + 1) % n;
        if (is_new[i] || is_new[ii])
            continue;
        uint32_t inner_prev = h[i], inner_next = h[ii];
        if (m->he_next[inner_prev] == inner_next)
            continue;
        uint32_t bprev = inner_next ^ 1u;
        size_t guard = 0;
        do {
            bprev = m->he_next[bprev] ^ 1u;
            if (++guard > m->nh) {
                st = GEOM_ERR_NONMANIFOLD;
                break;
            }
        } while (m->he_face[bprev] != INV || bprev == inner_prev);
        if (st != GEOM_OK)
            break;
        uint32_t bnext = m->he_next[bprev];
        if (bnext == inner_next) {
            st = GEOM_ERR_NONMANIFOLD; /* no other gap to move the patch to */
            break;
        }
        uint32_t patch_start = m->he_next[inner_prev], patch_end = m->he_prev[inner_next];
        log_set_next(m, &lg, bprev, patch_start);
        log_set_next(m, &lg, patch_end, bnext);
        log_set_next(m, &lg, inner_prev, inner_next);
    }
    if (st != GEOM_OK) {
        log_undo(m, &lg);
        goto done;
    }

    /* New edges and the face (capacity reserved above: cannot fail). */
    for (size_t i = 0; i < n; ++i) {
        if (!is_new[i])
            continue;
        uint32_t e0 = (uint32_t)m->nh;
        geom__mesh_resize(m, m->nv, m->nh + 2, m->nf);
        m->he_vertex[e0] = verts[(i + 1) % n];
        m->he_vertex[e0 + 1] = verts[i];
        h[i] = e0;
    }
    uint32_t f = (uint32_t)m->nf;
    geom__mesh_resize(m, m->nv, m->nh, m->nf + 1);
    m->f_he[f] = h[n - 1];

    size_t nc = 0;
#define CACHE(a, b) (cache[2 * nc] = (a), cache[2 * nc + 1] = (b), ++nc)
    for (size_t i = 0; i < n; ++i) {
        size_t ii = (i + 1) % n;
        uint32_t v = verts[ii], inner_prev = h[i], inner_next = h[ii];
        int id = (is_new[i] ? 1 : 0) | (is_new[ii] ? 2 : 0);
        adj[ii] = 0;
        if (id) {
            uint32_t outer_prev = inner_next ^ 1u, outer_next = inner_prev ^ 1u;
            if (id == 1) {
                uint32_t bprev = m->he_prev[inner_next];
                CACHE(bprev, outer_next);
                m->v_he[v] = outer_next;
            } else if (id == 2) {
                uint32_t bnext = m->he_next[inner_prev];
                CACHE(outer_prev, bnext);
                m->v_he[v] = bnext;
            } else if (m->v_he[v] == INV) {
                m->v_he[v] = outer_next;
                CACHE(outer_prev, outer_next);
            } else {
                uint32_t bnext = m->v_he[v], bprev = m->he_prev[bnext];
                CACHE(bprev, outer_next);
                CACHE(outer_prev, bnext);
            }
            CACHE(inner_prev, inner_next);
        } else
            adj[ii] = m->v_he[v] == inner_next;
        m->he_face[h[i]] = f;
    }
#undef CACHE
    for (size_t i = 0; i < nc; ++i)
        geom__mesh_link(m, cache[2 * i], cache[2 * i + 1]);
    for (size_t i = 0; i < n; ++i)
        if (adj[i])
            geom__mesh_adjust_outgoing(m, verts[i]);
    if (out)
        *out = f;
done:
    if (buf != sbuf)
        geom__free(&m->alloc, buf, words * sizeof(uint32_t));
    return st;
}

/* ------------------------------------------------------------ deletion */

static void mark_vertex_deleted(geom_mesh *m, uint32_t v)
{
    if (!m->v_del[v]) {
        m->v_del[v] = 1;
        m->n_del_v++;
    }
}

geom_status geom_mesh_delete_face(geom_mesh *m, uint32_t f)
{
    if (!FOK(m, f))
        return GEOM_ERR_INVALID_ARG;
    if (m->f_del[f])
        return GEOM_OK;
    size_t n = geom_mesh_face_valence(m, f);
    if (n == 0)
        return GEOM_ERR_INVALID_ARG;
    uint32_t sbuf[64];
    uint32_t *buf = sbuf;
    if (2 * n > 64) {
        buf = alloc_n(&m->alloc, 2 * n, sizeof(uint32_t));
        if (!buf)
            return GEOM_ERR_NOMEM;
    }
    uint32_t *dead = buf, *verts = buf + n;
    size_t nd = 0, k = 0;
    m->f_del[f] = 1;
    m->n_del_f++;
    uint32_t h0 = m->f_he[f], h = h0;
    do {
        m->he_face[h] = INV;
        for (size_t c = 0; c < m->n_channels; ++c)
            if (m->channels[c].domain == GEOM_MESH_DOMAIN_CORNER)
                m->channels[c].corner[h] = INV;
        if (m->he_face[h ^ 1u] == INV)
            dead[nd++] = h;
        verts[k++] = m->he_vertex[h];
        h = m->he_next[h];
    } while (h != h0);
    for (size_t i = 0; i < nd; ++i) {
        uint32_t h0e = dead[i] & ~1u, h1e = h0e | 1u;
        uint32_t v0 = m->he_vertex[h0e], v1 = m->he_vertex[h1e];
        uint32_t next0 = m->he_next[h0e], prev0 = m->he_prev[h0e];
        uint32_t next1 = m->he_next[h1e], prev1 = m->he_prev[h1e];
        geom__mesh_link(m, prev0, next1);
        geom__mesh_link(m, prev1, next0);
        if (!m->e_del[h0e >> 1]) {
            m->e_del[h0e >> 1] = 1;
            m->n_del_e++;
        }
        if (m->v_he[v0] == h1e) {
            if (next0 == h1e) {
                m->v_he[v0] = INV;
                mark_vertex_deleted(m, v0);
            } else
                m->v_he[v0] = next0;
        }
        if (m->v_he[v1] == h0e) {
            if (next1 == h0e) {
                m->v_he[v1] = INV;
                mark_vertex_deleted(m, v1);
            } else
                m->v_he[v1] = next1;
        }
    }
    for (size_t i = 0; i < k; ++i)
        if (!m->v_del[verts[i]])
            geom__mesh_adjust_outgoing(m, verts[i]);
    if (buf != sbuf)
        geom__free(&m->alloc, buf, 2 * n * sizeof(uint32_t));
    return GEOM_OK;
}

geom_status geom_mesh_delete_vertex(geom_mesh *m, uint32_t v)
{
    if (!VOK(m, v))
        return GEOM_ERR_INVALID_ARG;
    if (m->v_del[v])
        return GEOM_OK;
    /* Delete incident faces one at a time (each deletion changes the fan). */
    for (;;) {
        uint32_t h0 = m->v_del[v] ? INV : m->v_he[v];
        if (h0 == INV)
            break;
        uint32_t h = h0, f = INV;
        size_t guard = 0;
        do {
            if (m->he_face[h] != INV) {
                f = m->he_face[h];
                break;
            }
            h = geom__mesh_ccw(m, h);
        } while (h != h0 && ++guard <= m->nh);
        if (f == INV)
            break;
        geom_status s = geom_mesh_delete_face(m, f);
        if (s != GEOM_OK)
            return s;
    }
    m->v_he[v] = INV;
    mark_vertex_deleted(m, v);
    return GEOM_OK;
}

/* ---------------------------------------------------------- compaction */

static void compact_bytes(void *arr, size_t es, const uint32_t *map, size_t n)
{
    unsigned char *p = arr;
    for (size_t i = 0; i < n; ++i)
        if (map[i] != INV && map[i] != i)
            memmove(p + (size_t)map[i] * es, p + i * es, es);
}

geom_status geom_mesh_compact(geom_mesh *m, uint32_t *vertex_map, uint32_t *face_map)
{
    if (!m)
        return GEOM_ERR_INVALID_ARG;
    const geom_allocator *a = &m->alloc;
    size_t nv = m->nv, ne = m->nh / 2, nf = m->nf;
    uint32_t *vm = vertex_map, *fm = face_map, *em;
    if (!vm)
        vm = alloc_n(a, nv, 4);
    if (!fm)
        fm = alloc_n(a, nf, 4);
    em = alloc_n(a, ne, 4);
    geom_status st = GEOM_OK;
    if (!vm || !fm || !em) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    size_t k = 0;
    for (size_t i = 0; i < nv; ++i)
        vm[i] = m->v_del[i] ? INV : (uint32_t)k++;
    size_t nv2 = k;
    k = 0;
    for (size_t i = 0; i < ne; ++i)
        em[i] = m->e_del[i] ? INV : (uint32_t)k++;
    size_t ne2 = k;
    k = 0;
    for (size_t i = 0; i < nf; ++i)
        fm[i] = m->f_del[i] ? INV : (uint32_t)k++;
    size_t nf2 = k;

#define HMAP(h) ((h) == INV ? INV : (em[(h) >> 1] == INV ? INV : 2 * em[(h) >> 1] + ((h) & 1u)))
    /* vertices */
    for (size_t i = 0; i < nv; ++i) {
        if (vm[i] == INV)
            continue;
        uint32_t h = m->v_he[i];
        m->v_he[vm[i]] = HMAP(h);
    }
    if (m->vertex_origin)
        compact_bytes(m->vertex_origin, 4, vm, nv);
    /* halfedges */
    for (size_t e = 0; e < ne; ++e) {
        if (em[e] == INV)
            continue;
        for (uint32_t j = 0; j < 2; ++j) {
            uint32_t h = (uint32_t)(2 * e + j), d = 2 * em[e] + j;
            uint32_t nx = m->he_next[h], pv = m->he_prev[h], vx = m->he_vertex[h],
                     fc = m->he_face[h];
            m->he_next[d] = HMAP(nx);
            m->he_prev[d] = HMAP(pv);
            m->he_vertex[d] = vx == INV ? INV : vm[vx];
            m->he_face[d] = fc == INV ? INV : fm[fc];
        }
    }
    /* faces */
    for (size_t i = 0; i < nf; ++i) {
        if (fm[i] == INV)
            continue;
        uint32_t h = m->f_he[i];
        m->f_he[fm[i]] = HMAP(h);
    }
#undef HMAP
    if (m->face_origin)
        compact_bytes(m->face_origin, 4, fm, nf);
    if (m->face_flipped)
        compact_bytes(m->face_flipped, 1, fm, nf);
    if (m->face_group)
        compact_bytes(m->face_group, 4, fm, nf);
    for (size_t i = 0; i < m->n_channels; ++i) {
        geom__mesh_channel *c = &m->channels[i];
        size_t es = c->ncomp * sizeof(double);
        switch (c->domain) {
        case GEOM_MESH_DOMAIN_VERTEX: compact_bytes(c->data, es, vm, nv); break;
        case GEOM_MESH_DOMAIN_FACE: compact_bytes(c->data, es, fm, nf); break;
        case GEOM_MESH_DOMAIN_EDGE: compact_bytes(c->data, es, em, ne); break;
        case GEOM_MESH_DOMAIN_CORNER: compact_bytes(c->corner, 8, em, ne); break;
        }
    }
    geom__mesh_polylines_remap(m, vm);
    memset(m->v_del, 0, nv2);
    memset(m->e_del, 0, ne2);
    memset(m->f_del, 0, nf2);
    m->nv = nv2;
    m->nh = 2 * ne2;
    m->nf = nf2;
    m->n_del_v = m->n_del_e = m->n_del_f = 0;
done:
    if (vm != vertex_map)
        geom__free(a, vm, nv * 4);
    if (fm != face_map)
        geom__free(a, fm, nf * 4);
    geom__free(a, em, ne * 4);
    return st;
}
