/* meshio soup: what readers produce, validated and turned into a mesh with
 * geom_mesh_build, then decorated with channels, groups, tags, mtllibs and
 * polylines. */
#include "meshio/meshio_internal.h"
#include "mesh/mesh_internal.h"

#include <stdio.h>

void geom__meshio_soup_free(mio_soup *s, const geom_allocator *a)
{
    MIO_FREE(a, s->pos);
    MIO_FREE(a, s->fsize);
    MIO_FREE(a, s->fidx);
    MIO_FREE(a, s->floc);
    s->floc_n = 0;
    for (size_t i = 0; i < s->nchan; i++) {
        MIO_FREE(a, s->chan[i].val);
        MIO_FREE(a, s->chan[i].idx);
    }
    s->nchan = 0;
    MIO_FREE(a, s->fgroup);
    MIO_FREE(a, s->groups);
    MIO_FREE(a, s->strings);
    MIO_FREE(a, s->tags);
    MIO_FREE(a, s->tag_ints);
    MIO_FREE(a, s->tag_floats);
    MIO_FREE(a, s->tag_strs);
    MIO_FREE(a, s->mtllibs);
    MIO_FREE(a, s->pl_off);
    MIO_FREE(a, s->pl_verts);
}

mio_chan *geom__meshio_soup_chan(mio_soup *s, const geom_allocator *a, const char *name,
                                 geom_mesh_domain domain, size_t ncomp, const double *fill)
{
    for (size_t i = 0; i < s->nchan; i++)
        if (s->chan[i].domain == domain && strcmp(s->chan[i].name, name) == 0)
            return &s->chan[i];
    if (s->nchan == MIO_MAX_CHANNELS)
        return NULL;
    mio_chan *ch = &s->chan[s->nchan];
    memset(ch, 0, sizeof *ch);
    snprintf(ch->name, sizeof ch->name, "%s", name);
    ch->domain = domain;
    ch->ncomp = ncomp;
    size_t existing = domain == GEOM_MESH_DOMAIN_VERTEX ? mio_soup_nv(s)
                      : domain == GEOM_MESH_DOMAIN_FACE ? s->fsize.n
                                                        : 0;
    if (domain == GEOM_MESH_DOMAIN_CORNER) {
        if (MIO_RESERVE(a, ch->idx, s->fidx.n) != GEOM_OK)
            return NULL;
        for (size_t i = 0; i < s->fidx.n; i++)
            ch->idx.p[i] = GEOM_INVALID_INDEX;
        ch->idx.n = s->fidx.n;
    } else if (existing) {
        size_t need;
        if (geom__size_mul(existing, ncomp, &need) != GEOM_OK ||
            MIO_RESERVE(a, ch->val, need) != GEOM_OK)
            return NULL;
        for (size_t i = 0; i < existing; i++)
            for (size_t k = 0; k < ncomp; k++)
                ch->val.p[i * ncomp + k] = fill ? fill[k] : 0.0;
        ch->val.n = need;
    }
    s->nchan++;
    return ch;
}

geom_status geom__meshio_soup_str(mio_soup *s, const geom_allocator *a, const char *str,
                                  size_t len, size_t *off)
{
    if (len > SIZE_MAX - 1 || MIO_RESERVE(a, s->strings, len + 1) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    *off = s->strings.n;
    memcpy(s->strings.p + s->strings.n, str, len);
    s->strings.p[s->strings.n + len] = '\0';
    s->strings.n += len + 1;
    return GEOM_OK;
}

geom_status geom__meshio_check_count(mio_ctx *c, size_t n, const char *what, uint64_t loc,
                                     int loc_is_offset)
{
    if (n <= c->max_elements)
        return GEOM_OK;
    if (loc_is_offset)
        return geom__meshio_err_off(c, GEOM_ERR_LIMIT, loc,
                                    "%zu %s exceed the limit of %zu elements", n, what,
                                    c->max_elements);
    return geom__meshio_err_line(c, GEOM_ERR_LIMIT, (size_t)loc, 0,
                                 "%zu %s exceed the limit of %zu elements", n, what,
                                 c->max_elements);
}

/* ------------------------------------------------------------- validation */

uint64_t geom__meshio_floc(const mio_soup *s, size_t f)
{
    if (f >= s->floc_n || s->floc.n == 0)
        return 0;
    size_t lo = 0, hi = s->floc.n - 1; /* the last run with face0 <= f */
    while (lo < hi) {
        size_t mid = lo + (hi - lo + 1) / 2;
        if (s->floc.p[mid].face0 <= f)
            lo = mid;
        else
            hi = mid - 1;
    }
    const mio_locrun *r = &s->floc.p[lo];
    return r->loc0 + (uint64_t)r->step * (f - r->face0);
}

static geom_status face_error(mio_ctx *c, const mio_soup *s, size_t f, const char *msg)
{
    uint64_t loc = geom__meshio_floc(s, f);
    if (s->loc_is_offset)
        return geom__meshio_err_off(c, GEOM_ERR_PARSE, loc, "face %zu: %s", f + 1, msg);
    return geom__meshio_err_line(c, GEOM_ERR_PARSE, (size_t)loc, 0, "face %zu: %s", f + 1, msg);
}

static geom_status validate_faces(mio_ctx *c, const mio_soup *s, size_t *n_invalid)
{
    size_t nv = mio_soup_nv(s);
    *n_invalid = 0;
    uint32_t *stamp = NULL;
    size_t bytes = 0;
    if (nv) {
        if (geom__size_mul(nv, sizeof(uint32_t), &bytes) != GEOM_OK)
            return GEOM_ERR_LIMIT;
        stamp = geom__alloc(c->alloc, bytes);
        if (!stamp)
            return GEOM_ERR_NOMEM;
        memset(stamp, 0xff, bytes);
    }
    geom_status st = GEOM_OK;
    size_t off = 0;
    for (size_t f = 0; f < s->fsize.n && st == GEOM_OK; f++) {
        size_t n = s->fsize.p[f];
        size_t first = off;
        off += n;
        int bad = 0;
        if (n < 3) {
            bad = 1;
            if (!c->skip_invalid) {
                char msg[160];
                snprintf(msg, sizeof msg, "expected at least 3 vertices, found %zu", n);
                st = face_error(c, s, f, msg);
                if (c->diag)
                    c->diag->hint = GEOM_DIAG_HINT_SKIP_INVALID_FACES;
            }
            (*n_invalid)++;
            continue;
        }
        const uint32_t *ix = s->fidx.p + first; /* n >= 3: not NULL */
        for (size_t k = 0; k < n && !bad; k++) {
            uint32_t v = ix[k];
            if (v >= nv) { /* readers check this; keep the build safe anyway */
                bad = 1;
                if (!c->skip_invalid) {
                    char msg[160];
                    snprintf(msg, sizeof msg, "vertex index %zu out of range (%zu vertices)",
                             (size_t)v + 1, nv);
                    st = face_error(c, s, f, msg);
                }
            } else if (stamp[v] == (uint32_t)f) {
                bad = 1;
                if (!c->skip_invalid) {
                    char msg[160];
                    snprintf(msg, sizeof msg,
                             "vertex %zu appears twice (again at corner %zu): expected "
                             "distinct vertices",
                             (size_t)v + 1, k + 1);
                    st = face_error(c, s, f, msg);
                    if (c->diag)
                        c->diag->hint = GEOM_DIAG_HINT_SKIP_INVALID_FACES;
                }
            } else {
                stamp[v] = (uint32_t)f;
            }
        }
        if (bad)
            (*n_invalid)++;
    }
    geom__free(c->alloc, stamp, bytes);
    return st;
}

/* ------------------------------------------------------------ decoration */

static const char *soup_string(const mio_soup *s, size_t off)
{
    return off == MIO_NOSTR ? NULL : s->strings.p + off;
}

/* Corner channels: for each output face, find the input corner of each
 * halfedge by the input vertex it came from. */
static geom_status copy_corners(mio_ctx *c, const mio_soup *s, geom_mesh *m)
{
    size_t nf = geom_mesh_n_faces(m);
    const uint32_t *vorig = geom_mesh_vertex_origin(m);
    const uint32_t *forig = geom_mesh_face_origin(m);
    size_t nin = s->fsize.n;
    size_t *start = NULL;
    size_t bytes = 0;
    int any = 0;
    for (size_t i = 0; i < s->nchan; i++)
        any |= s->chan[i].domain == GEOM_MESH_DOMAIN_CORNER;
    if (!any)
        return GEOM_OK;
    if (geom__size_mul(nin + 1, sizeof(size_t), &bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    start = geom__alloc(c->alloc, bytes);
    if (!start)
        return GEOM_ERR_NOMEM;
    start[0] = 0;
    for (size_t f = 0; f < nin; f++)
        start[f + 1] = start[f] + s->fsize.p[f];

    uint32_t ids[MIO_MAX_CHANNELS];
    uint32_t *cidx[MIO_MAX_CHANNELS];
    const mio_chan *chans[MIO_MAX_CHANNELS];
    size_t nc = 0;
    geom_status st = GEOM_OK;
    for (size_t i = 0; i < s->nchan && st == GEOM_OK; i++) {
        const mio_chan *ch = &s->chan[i];
        if (ch->domain != GEOM_MESH_DOMAIN_CORNER)
            continue;
        uint32_t id = geom_mesh_channel_find(m, ch->name, GEOM_MESH_DOMAIN_CORNER);
        if (id == GEOM_INVALID_INDEX)
            st = geom_mesh_channel_add(m, ch->name, GEOM_MESH_DOMAIN_CORNER, ch->ncomp, &id);
        if (st != GEOM_OK)
            break;
        size_t pool = ch->val.n / ch->ncomp;
        st = geom_mesh_corner_pool_resize(m, id, pool);
        if (st != GEOM_OK)
            break;
        if (pool)
            memcpy(geom_mesh_channel_data(m, id), ch->val.p, ch->val.n * sizeof(double));
        ids[nc] = id;
        chans[nc] = ch;
        nc++;
    }
    for (size_t k = 0; k < nc && st == GEOM_OK; k++) {
        cidx[k] = geom_mesh_corner_indices(m, ids[k]);
        if (!cidx[k])
            st = GEOM_ERR_NOMEM;
    }
    for (size_t f = 0; f < nf && st == GEOM_OK; f++) {
        if (geom_mesh_face_is_deleted(m, (uint32_t)f))
            continue;
        size_t fi = forig ? forig[f] : f;
        if (fi >= nin)
            continue; /* not an input face: leave its corners unset */
        const uint32_t *in = s->fidx.p + start[fi];
        size_t n = s->fsize.p[fi];
        uint32_t h0 = geom_mesh_face_he(m, (uint32_t)f);
        uint32_t h = h0;
        size_t k = SIZE_MAX; /* input corner of the current halfedge */
        int dir = 0;         /* +1 same order as input, -1 reversed */
        size_t guard = 0;
        do {
            uint32_t v = geom_mesh_he_vertex(m, h);
            uint32_t vo = vorig ? vorig[v] : v;
            size_t want = k == SIZE_MAX ? SIZE_MAX
                                        : dir >= 0 ? (k + 1) % n : (k + n - 1) % n;
            size_t found = SIZE_MAX;
            if (want != SIZE_MAX && in[want] == vo) {
                found = want;
            } else if (k != SIZE_MAX && dir == 0 && in[(k + n - 1) % n] == vo) {
                found = (k + n - 1) % n;
            } else {
                for (size_t j = 0; j < n; j++)
                    if (in[j] == vo) {
                        found = j;
                        break;
                    }
            }
            if (found != SIZE_MAX && k != SIZE_MAX && dir == 0)
                dir = found == (k + 1) % n ? 1 : -1;
            k = found;
            if (k != SIZE_MAX) {
                for (size_t q = 0; q < nc; q++)
                    cidx[q][h] = chans[q]->idx.p[start[fi] + k];
            }
            h = geom_mesh_he_next(m, h);
        } while (h != h0 && h != GEOM_INVALID_INDEX && ++guard <= n + 1);
    }
    geom__free(c->alloc, start, bytes);
    return st;
}

static geom_status copy_element_channels(const mio_soup *s, geom_mesh *m)
{
    size_t nv = geom_mesh_n_vertices(m), nf = geom_mesh_n_faces(m);
    const uint32_t *vorig = geom_mesh_vertex_origin(m);
    const uint32_t *forig = geom_mesh_face_origin(m);
    size_t sv = mio_soup_nv(s), sf = s->fsize.n;
    for (size_t i = 0; i < s->nchan; i++) {
        const mio_chan *ch = &s->chan[i];
        if (ch->domain == GEOM_MESH_DOMAIN_CORNER)
            continue;
        int isv = ch->domain == GEOM_MESH_DOMAIN_VERTEX;
        uint32_t id;
        geom_status st = geom_mesh_channel_add(m, ch->name, ch->domain, ch->ncomp, &id);
        if (st != GEOM_OK)
            return st;
        double *dst = geom_mesh_channel_data(m, id);
        size_t n = isv ? nv : nf;
        const uint32_t *orig = isv ? vorig : forig;
        size_t nsrc = isv ? sv : sf;
        for (size_t e = 0; e < n; e++) {
            size_t o = orig ? orig[e] : e;
            if (o >= nsrc || (o + 1) * ch->ncomp > ch->val.n)
                continue; /* zero-filled */
            memcpy(dst + e * ch->ncomp, ch->val.p + o * ch->ncomp, ch->ncomp * sizeof(double));
        }
    }
    return GEOM_OK;
}

static geom_status copy_meta(const mio_soup *s, geom_mesh *m, const geom_allocator *a)
{
    geom_status st = GEOM_OK;
    for (size_t i = 0; i < s->mtllibs.n && st == GEOM_OK; i++)
        st = geom_mesh_mtllib_add(m, soup_string(s, s->mtllibs.p[i]));
    for (size_t i = 0; i < s->tags.n && st == GEOM_OK; i++) {
        const mio_tagrec *t = &s->tags.p[i];
        const char **strs = NULL;
        size_t bytes = t->nstring * sizeof(char *);
        if (t->nstring) {
            strs = geom__alloc(a, bytes);
            if (!strs)
                return GEOM_ERR_NOMEM;
            for (size_t k = 0; k < t->nstring; k++)
                strs[k] = soup_string(s, s->tag_strs.p[t->strs + k]);
        }
        geom_mesh_tag tag;
        tag.name = soup_string(s, t->name);
        tag.nint = t->nint;
        tag.nfloat = t->nfloat;
        tag.nstring = t->nstring;
        tag.ints = t->nint ? s->tag_ints.p + t->ints : NULL;
        tag.floats = t->nfloat ? s->tag_floats.p + t->floats : NULL;
        tag.strings = strs;
        st = geom_mesh_tag_add(m, &tag);
        geom__free(a, strs, bytes);
    }
    for (size_t i = 0; i + 1 < s->pl_off.n && st == GEOM_OK; i++)
        st = geom_mesh_polyline_add(m, s->pl_off.p[i + 1] - s->pl_off.p[i],
                                    s->pl_verts.p + s->pl_off.p[i]);
    if (st != GEOM_OK || s->groups.n == 0)
        return st;
    size_t ng = s->groups.n / 4;
    for (size_t g = 0; g < ng && st == GEOM_OK; g++) {
        geom_mesh_group grp;
        grp.group = soup_string(s, s->groups.p[4 * g + 0]);
        grp.object = soup_string(s, s->groups.p[4 * g + 1]);
        grp.material = soup_string(s, s->groups.p[4 * g + 2]);
        grp.smoothing = soup_string(s, s->groups.p[4 * g + 3]);
        st = geom_mesh_group_add(m, &grp, NULL);
    }
    if (st != GEOM_OK)
        return st;
    size_t nf = geom_mesh_n_faces(m);
    if (nf == 0)
        return GEOM_OK;
    uint32_t *fg = geom_mesh_face_groups(m);
    if (!fg)
        return GEOM_ERR_NOMEM;
    const uint32_t *forig = geom_mesh_face_origin(m);
    for (size_t f = 0; f < nf; f++) {
        size_t o = forig ? forig[f] : f;
        fg[f] = o < s->fgroup.n ? s->fgroup.p[o] : GEOM_INVALID_INDEX;
    }
    return GEOM_OK;
}

geom_status geom__meshio_soup_finish(mio_ctx *c, mio_soup *s, const geom_meshio_read_options *opt,
                                     geom_mesh **out, geom_mesh_build_report *report)
{
    c->stats->input_vertices = mio_soup_nv(s);
    c->stats->input_faces = s->fsize.n;
    geom_mesh *m = geom_mesh_create(c->alloc);
    if (!m)
        return geom__meshio_err_line(c, GEOM_ERR_NOMEM, 0, 0, "out of memory");
    geom_mesh_build_options bo;
    memset(&bo, 0, sizeof bo);
    if (opt)
        bo = opt->build;
    /* The positions move into the mesh instead of being copied (one copy
     * fewer at the build's peak): trimmed to size, then adopted. On any
     * failure the build copies them as usual. */
    size_t nv = mio_soup_nv(s);
    const double *xyz = s->pos.p;
    if (nv && s->pos.n == 3 * nv) {
        double *exact = s->pos.p;
        if (s->pos.cap != s->pos.n)
            exact = geom__realloc(c->alloc, s->pos.p, s->pos.cap * sizeof(double),
                                 s->pos.n * sizeof(double));
        if (exact) {
            s->pos.p = exact;
            s->pos.cap = s->pos.n;
            xyz = exact;
            if (geom__mesh_adopt_positions(m, exact, nv) == GEOM_OK) {
                s->pos.p = NULL; /* the mesh's now; pos.n still counts them */
                s->pos.cap = 0;
            }
        }
    }
    /* The build checks the faces; only when it refuses one are they checked
     * here again, for a message naming the face's line. */
    geom_status st = geom_mesh_build(m, nv, xyz, s->fsize.n, s->fsize.p, s->fidx.p, &bo, report,
                                     c->diag);
    if (st == GEOM_ERR_INVALID_ARG && !c->skip_invalid) {
        size_t n_invalid = 0;
        geom_status vs = validate_faces(c, s, &n_invalid);
        if (vs != GEOM_OK)
            st = vs;
    }
    MIO_FREE(c->alloc, s->floc); /* face locations serve diagnostics only: done */
    s->floc_n = 0;
    if (st != GEOM_OK) {
        if (c->diag && c->diag->source[0] == '\0')
            snprintf(c->diag->source, sizeof c->diag->source, "%s", c->source);
        geom_mesh_destroy(m);
        return st;
    }
    st = copy_element_channels(s, m);
    if (st == GEOM_OK)
        st = copy_corners(c, s, m);
    if (st == GEOM_OK)
        st = copy_meta(s, m, c->alloc);
    if (st != GEOM_OK) {
        geom_mesh_destroy(m);
        return geom__meshio_err_line(c, st, 0, 0, "%s while storing attributes",
                                     geom_status_str(st));
    }
    *out = m;
    return GEOM_OK;
}
