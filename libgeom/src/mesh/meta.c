/* Mesh metadata: subdivision tags, face groups, material libraries and
 * polylines. */
#include "mesh/mesh_internal.h"

#define INV GEOM_INVALID_INDEX

/* ---------------------------------------------------------------- tags */

static void tag_free(const geom_allocator *a, geom__mesh_tag *t)
{
    geom__mesh_strfree(a, t->name);
    geom__free(a, t->ints, t->nint * sizeof(int64_t));
    geom__free(a, t->floats, t->nfloat * sizeof(double));
    if (t->strings) {
        for (size_t i = 0; i < t->nstring; ++i)
            geom__mesh_strfree(a, t->strings[i]);
        geom__free(a, t->strings, t->nstring * sizeof(char *));
    }
    memset(t, 0, sizeof *t);
}

static void group_free(const geom_allocator *a, geom__mesh_group *g)
{
    for (int i = 0; i < 4; ++i)
        geom__mesh_strfree(a, g->s[i]);
    memset(g, 0, sizeof *g);
}

size_t geom_mesh_tag_count(const geom_mesh *m) { return m ? m->n_tags : 0; }

geom_status geom_mesh_tag_get(const geom_mesh *m, size_t i, geom_mesh_tag *out)
{
    if (!m || !out || i >= m->n_tags)
        return GEOM_ERR_INVALID_ARG;
    const geom__mesh_tag *t = &m->tags[i];
    out->name = t->name;
    out->nint = t->nint;
    out->nfloat = t->nfloat;
    out->nstring = t->nstring;
    out->ints = t->ints;
    out->floats = t->floats;
    out->strings = (const char *const *)t->strings;
    return GEOM_OK;
}

geom_status geom_mesh_tag_add(geom_mesh *m, const geom_mesh_tag *tag)
{
    if (!m || !tag || !tag->name || (tag->nint && !tag->ints) ||
        (tag->nfloat && !tag->floats) || (tag->nstring && !tag->strings))
        return GEOM_ERR_INVALID_ARG;
    for (size_t i = 0; i < tag->nstring; ++i)
        if (!tag->strings[i])
            return GEOM_ERR_INVALID_ARG;
    const geom_allocator *a = &m->alloc;
    void *arr = m->tags;
    geom_status s = geom__grow(a, &arr, &m->cap_tags, m->n_tags + 1, sizeof *m->tags);
    m->tags = arr;
    if (s != GEOM_OK)
        return s;
    geom__mesh_tag t;
    memset(&t, 0, sizeof t);
    size_t bi, bf, bs;
    if (geom__size_mul(tag->nint, sizeof(int64_t), &bi) != GEOM_OK ||
        geom__size_mul(tag->nfloat, sizeof(double), &bf) != GEOM_OK ||
        geom__size_mul(tag->nstring, sizeof(char *), &bs) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    if ((s = geom__mesh_strdup(a, tag->name, &t.name)) != GEOM_OK)
        goto fail;
    s = GEOM_ERR_NOMEM;
    if (tag->nint) {
        if (!(t.ints = geom__alloc(a, bi)))
            goto fail;
        memcpy(t.ints, tag->ints, bi);
        t.nint = tag->nint;
    }
    if (tag->nfloat) {
        if (!(t.floats = geom__alloc(a, bf)))
            goto fail;
        memcpy(t.floats, tag->floats, bf);
        t.nfloat = tag->nfloat;
    }
    if (tag->nstring) {
        if (!(t.strings = geom__alloc(a, bs)))
            goto fail;
        memset(t.strings, 0, bs);
        t.nstring = tag->nstring;
        for (size_t i = 0; i < tag->nstring; ++i)
            if (geom__mesh_strdup(a, tag->strings[i], &t.strings[i]) != GEOM_OK)
                goto fail;
    }
    m->tags[m->n_tags++] = t;
    return GEOM_OK;
fail:
    tag_free(a, &t);
    return s;
}

/* -------------------------------------------------------------- groups */

size_t geom_mesh_group_count(const geom_mesh *m) { return m ? m->n_groups : 0; }

geom_status geom_mesh_group_get(const geom_mesh *m, size_t i, geom_mesh_group *out)
{
    if (!m || !out || i >= m->n_groups)
        return GEOM_ERR_INVALID_ARG;
    const geom__mesh_group *g = &m->groups[i];
    out->group = g->s[0];
    out->object = g->s[1];
    out->material = g->s[2];
    out->smoothing = g->s[3];
    return GEOM_OK;
}

geom_status geom_mesh_group_add(geom_mesh *m, const geom_mesh_group *g, uint32_t *id)
{
    if (!m || !g)
        return GEOM_ERR_INVALID_ARG;
    if (m->n_groups >= (size_t)UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;
    const geom_allocator *a = &m->alloc;
    void *arr = m->groups;
    geom_status s = geom__grow(a, &arr, &m->cap_groups, m->n_groups + 1, sizeof *m->groups);
    m->groups = arr;
    if (s != GEOM_OK)
        return s;
    geom__mesh_group n;
    memset(&n, 0, sizeof n);
    const char *src[4] = {g->group, g->object, g->material, g->smoothing};
    for (int i = 0; i < 4; ++i)
        if (geom__mesh_strdup(a, src[i], &n.s[i]) != GEOM_OK) {
            group_free(a, &n);
            return GEOM_ERR_NOMEM;
        }
    if (id)
        *id = (uint32_t)m->n_groups;
    m->groups[m->n_groups++] = n;
    return GEOM_OK;
}

uint32_t *geom_mesh_face_groups(geom_mesh *m)
{
    if (!m)
        return NULL;
    if (!m->face_group) {
        if (geom__mesh_reserve_some(m) != GEOM_OK)
            return NULL;
        size_t nb;
        if (geom__size_mul(m->cap_f, sizeof(uint32_t), &nb) != GEOM_OK)
            return NULL;
        uint32_t *p = geom__alloc(&m->alloc, nb);
        if (!p)
            return NULL;
        for (size_t i = 0; i < m->cap_f; ++i)
            p[i] = INV;
        m->face_group = p;
    }
    return m->face_group;
}

const uint32_t *geom_mesh_face_cgroups(const geom_mesh *m) { return m ? m->face_group : NULL; }

/* ------------------------------------------------------------- mtllibs */

size_t geom_mesh_mtllib_count(const geom_mesh *m) { return m ? m->n_mtllibs : 0; }

const char *geom_mesh_mtllib_get(const geom_mesh *m, size_t i)
{
    return m && i < m->n_mtllibs ? m->mtllibs[i] : NULL;
}

geom_status geom_mesh_mtllib_add(geom_mesh *m, const char *name)
{
    if (!m || !name)
        return GEOM_ERR_INVALID_ARG;
    void *arr = m->mtllibs;
    geom_status s =
        geom__grow(&m->alloc, &arr, &m->cap_mtllibs, m->n_mtllibs + 1, sizeof(char *));
    m->mtllibs = arr;
    if (s != GEOM_OK)
        return s;
    char *d;
    if ((s = geom__mesh_strdup(&m->alloc, name, &d)) != GEOM_OK)
        return s;
    m->mtllibs[m->n_mtllibs++] = d;
    return GEOM_OK;
}

/* ----------------------------------------------------------- polylines */

size_t geom_mesh_polyline_count(const geom_mesh *m) { return m ? m->n_polylines : 0; }

geom_status geom_mesh_polyline_get(const geom_mesh *m, size_t i, size_t *n,
                                   const uint32_t **verts)
{
    if (!m || i >= m->n_polylines)
        return GEOM_ERR_INVALID_ARG;
    if (n)
        *n = m->pl_off[i + 1] - m->pl_off[i];
    if (verts)
        *verts = m->pl_verts + m->pl_off[i];
    return GEOM_OK;
}

geom_status geom_mesh_polyline_add(geom_mesh *m, size_t n, const uint32_t *verts)
{
    if (!m || (n && !verts))
        return GEOM_ERR_INVALID_ARG;
    const geom_allocator *a = &m->alloc;
    /* offsets: cap_polylines + 1 entries */
    size_t need = m->n_polylines + 2, cap = m->cap_polylines ? m->cap_polylines + 1 : 0;
    void *arr = m->pl_off;
    geom_status s = geom__grow(a, &arr, &cap, need, sizeof(size_t));
    m->pl_off = arr;
    if (s != GEOM_OK)
        return s;
    m->cap_polylines = cap - 1;
    if (m->n_polylines == 0)
        m->pl_off[0] = 0;
    arr = m->pl_verts;
    s = geom__grow(a, &arr, &m->cap_pl_verts, m->pl_nverts + n, sizeof(uint32_t));
    m->pl_verts = arr;
    if (s != GEOM_OK)
        return s;
    if (n)
        memcpy(m->pl_verts + m->pl_nverts, verts, n * sizeof(uint32_t));
    m->pl_nverts += n;
    m->n_polylines++;
    m->pl_off[m->n_polylines] = m->pl_nverts;
    return GEOM_OK;
}

void geom__mesh_polylines_remap(geom_mesh *m, const uint32_t *vmap)
{
    size_t w = 0, start = 0;
    for (size_t i = 0; i < m->n_polylines; ++i) {
        size_t end = m->pl_off[i + 1];
        size_t s0 = w;
        for (size_t k = start; k < end; ++k) {
            uint32_t v = m->pl_verts[k];
            uint32_t nv = (size_t)v < m->nv ? vmap[v] : GEOM_INVALID_INDEX;
            if (nv != GEOM_INVALID_INDEX)
                m->pl_verts[w++] = nv;
        }
        start = end;
        m->pl_off[i] = s0;
        m->pl_off[i + 1] = w;
    }
    m->pl_nverts = w;
}

/* ------------------------------------------------------- free and copy */

void geom__mesh_meta_free(geom_mesh *m)
{
    const geom_allocator *a = &m->alloc;
    for (size_t i = 0; i < m->n_tags; ++i)
        tag_free(a, &m->tags[i]);
    geom__free(a, m->tags, m->cap_tags * sizeof *m->tags);
    m->tags = NULL;
    m->n_tags = m->cap_tags = 0;
    for (size_t i = 0; i < m->n_groups; ++i)
        group_free(a, &m->groups[i]);
    geom__free(a, m->groups, m->cap_groups * sizeof *m->groups);
    m->groups = NULL;
    m->n_groups = m->cap_groups = 0;
    for (size_t i = 0; i < m->n_mtllibs; ++i)
        geom__mesh_strfree(a, m->mtllibs[i]);
    geom__free(a, m->mtllibs, m->cap_mtllibs * sizeof(char *));
    m->mtllibs = NULL;
    m->n_mtllibs = m->cap_mtllibs = 0;
    geom__free(a, m->pl_off, (m->cap_polylines ? m->cap_polylines + 1 : 0) * sizeof(size_t));
    geom__free(a, m->pl_verts, m->cap_pl_verts * sizeof(uint32_t));
    m->pl_off = NULL;
    m->pl_verts = NULL;
    m->n_polylines = m->cap_polylines = m->pl_nverts = m->cap_pl_verts = 0;
}

geom_status geom__mesh_meta_copy(geom_mesh *dst, const geom_mesh *src)
{
    geom_status s;
    for (size_t i = 0; i < src->n_tags; ++i) {
        geom_mesh_tag t;
        geom_mesh_tag_get(src, i, &t);
        if ((s = geom_mesh_tag_add(dst, &t)) != GEOM_OK)
            return s;
    }
    for (size_t i = 0; i < src->n_groups; ++i) {
        geom_mesh_group g;
        geom_mesh_group_get(src, i, &g);
        if ((s = geom_mesh_group_add(dst, &g, NULL)) != GEOM_OK)
            return s;
    }
    for (size_t i = 0; i < src->n_mtllibs; ++i)
        if ((s = geom_mesh_mtllib_add(dst, src->mtllibs[i])) != GEOM_OK)
            return s;
    for (size_t i = 0; i < src->n_polylines; ++i) {
        size_t n;
        const uint32_t *v;
        geom_mesh_polyline_get(src, i, &n, &v);
        if ((s = geom_mesh_polyline_add(dst, n, v)) != GEOM_OK)
            return s;
    }
    return GEOM_OK;
}
